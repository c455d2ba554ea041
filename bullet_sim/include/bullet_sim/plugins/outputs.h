// What plugins produce and take, in ROS message terms but without ROS: the node's adapter maps each type to
// its message once.
#pragma once

#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace bullet_sim {

/// nav_msgs/Odometry.
struct Odometry {
  double stamp = 0;  ///< sim time [s]
  std::string frame_id;
  std::string child_frame_id;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();      ///< child frame in frame_id
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();   ///< [m/s] in the child frame
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  ///< [rad/s] in the child frame
  std::array<double, 36> pose_covariance{};
  std::array<double, 36> twist_covariance{};
};

/// sensor_msgs/JointState.
struct JointStateSample {
  double stamp = 0;
  std::vector<std::string> names;
  std::vector<double> positions;   ///< [rad] or [m]
  std::vector<double> velocities;  ///< [rad/s] or [m/s]
  std::vector<double> efforts;     ///< [N m] or [N]
};

/// sensor_msgs/LaserScan, plus where the sensor was (for drawing the hits).
struct LaserScan {
  double stamp = 0;
  std::string frame_id;
  double angle_min = 0;  ///< [rad]
  double angle_max = 0;
  double angle_increment = 0;
  double scan_time = 0;  ///< [s] between scans
  double range_min = 0;  ///< [m]
  double range_max = 0;
  std::vector<float> ranges;  ///< [m]; +inf: no return within range_max; -inf: closer than range_min
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();  ///< in the world, when the scan was taken
};

/// sensor_msgs/PointCloud2: the in-range returns of a lidar, in its frame.
struct PointCloud {
  double stamp = 0;
  std::string frame_id;
  std::vector<Eigen::Vector3f> points;  ///< [m] in the sensor frame
  std::vector<float> intensities;  ///< per point; 1 for every return (surfaces have no reflectivity here)
  std::vector<uint16_t> rings;     ///< the channel of each point, 0 = bottom
  Eigen::Isometry3d sensor_pose = Eigen::Isometry3d::Identity();  ///< in the world, when the scan was taken
};

/// sensor_msgs/PointCloud, the older message (libgazebo_ros_block_laser.so publishes it).
struct LegacyPointCloud : PointCloud {};

/// Transforms for /tf, all of one stamp.
struct TransformSample {
  struct Frame {
    std::string parent;
    std::string child;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< child in parent
  };
  double stamp = 0;
  std::vector<Frame> frames;
};

/// sensor_msgs/Imu.
struct ImuSample {
  double stamp = 0;
  std::string frame_id;
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();  ///< of the frame in the world
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();       ///< [rad/s] in the frame
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  ///< [m/s^2] in the frame, gravity included
  /// The covariances' diagonals (x, y, z).
  Eigen::Vector3d orientation_variance = Eigen::Vector3d::Zero();
  Eigen::Vector3d angular_velocity_variance = Eigen::Vector3d::Zero();
  Eigen::Vector3d linear_acceleration_variance = Eigen::Vector3d::Zero();
};

/// sensor_msgs/Image: a camera's colour image or a depth image, as its ROS encoding lays it out.
struct CameraImage {
  double stamp = 0;
  std::string frame_id;
  int width = 0;  ///< [px]
  int height = 0;
  std::string encoding;  ///< rgb8, bgr8, mono8, 32FC1 (depth [m]) or 16UC1 (depth [mm])
  int step = 0;          ///< bytes per row
  std::vector<uint8_t> data;  ///< rows top first; multi-byte values in the machine's (little-endian) order
};

/// sensor_msgs/CameraInfo, with the ROS field names. `camera_name` is where the node's camera_info_manager
/// lives (its set_camera_info service), relative to the plugin's namespace.
struct CameraInfo {
  double stamp = 0;
  std::string frame_id;
  std::string camera_name;
  int width = 0;
  int height = 0;
  std::string distortion_model = "plumb_bob";
  std::array<double, 5> D{};  ///< k1, k2, t1, t2, k3
  std::array<double, 9> K{};
  std::array<double, 9> R{1, 0, 0, 0, 1, 0, 0, 0, 1};
  std::array<double, 12> P{};
};

/// An organized sensor_msgs/PointCloud2 (x y z rgb) of width x height points, rows top first, in the optical
/// convention (z along the view, x right, y down); NaN where the depth is outside the cloud's cut-offs.
struct ColouredCloud {
  double stamp = 0;
  std::string frame_id;
  int width = 0;
  int height = 0;
  std::vector<Eigen::Vector3f> points;        ///< [m]
  std::vector<std::array<uint8_t, 3>> rgb;  ///< per point
  bool is_dense = true;                       ///< false when any point is NaN
};

/// control_msgs/JointControllerState: what a PID joint controller aims at, sees and commands, with its gains.
struct JointControllerState {
  double stamp = 0;
  double set_point = 0;          ///< [rad], [m], [rad/s] or [m/s]: what the controller aims at
  double process_value = 0;      ///< what it measures
  double process_value_dot = 0;  ///< its time derivative (0 where the controller does not fill it)
  double error = 0;              ///< set_point - process_value
  double time_step = 0;          ///< [s] since the previous update
  double command = 0;            ///< [N m] or [N]
  double p = 0, i = 0, d = 0, i_clamp = 0;
  bool antiwindup = false;
};

/// sensor_msgs/Range: the nearest hit of a ranger's rays.
struct RangeSample {
  double stamp = 0;
  std::string frame_id;
  bool infrared = false;      ///< radiation_type INFRARED (1), else ULTRASOUND (0)
  double field_of_view = 0;   ///< [rad]
  double min_range = 0;       ///< [m]
  double max_range = 0;       ///< [m]
  double range = 0;           ///< [m]
};

/// sensor_msgs/NavSatFix.
struct NavSatFixSample {
  double stamp = 0;
  std::string frame_id;
  int status = 0;        ///< NavSatStatus: -1 no fix, 0 fix, 1 SBAS fix, 2 GBAS fix
  unsigned service = 0;  ///< NavSatStatus service bits: 1 GPS, 2 GLONASS, 4 COMPASS, 8 GALILEO
  double latitude = 0;   ///< [deg], + north
  double longitude = 0;  ///< [deg], + east
  double altitude = 0;   ///< [m] above the WGS84 ellipsoid
  std::array<double, 9> position_covariance{};  ///< [m^2], row-major, east north up
  int position_covariance_type = 0;  ///< 0 unknown, 1 approximated, 2 diagonal known, 3 known
};

/// geometry_msgs/Vector3Stamped.
struct Vector3Sample {
  double stamp = 0;
  std::string frame_id;
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();
};

/// gazebo_msgs/ContactsState: what touches a contact sensor's collisions, one state per pair of collisions.
struct ContactsSample {
  struct Wrench {
    Eigen::Vector3d force = Eigen::Vector3d::Zero();   ///< [N]
    Eigen::Vector3d torque = Eigen::Vector3d::Zero();  ///< [N m]
  };
  struct State {
    std::string info;
    std::string collision1;  ///< the sensor's collision, model::link::collision as Gazebo names it
    std::string collision2;  ///< what it touches
    std::vector<Wrench> wrenches;  ///< per contact point, on collision1
    Wrench total_wrench;
    std::vector<Eigen::Vector3d> positions;  ///< [m]
    std::vector<Eigen::Vector3d> normals;    ///< unit
    std::vector<double> depths;              ///< [m] of interpenetration
  };
  double stamp = 0;
  std::string frame_id;
  std::vector<State> states;  ///< empty while nothing touches
};

/// geometry_msgs/Twist, an input: a velocity command.
struct Twist {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   ///< [m/s]
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  ///< [rad/s]
};

/// geometry_msgs/TwistStamped: a velocity command as a controller applies it.
struct StampedTwist {
  double stamp = 0;
  std::string frame_id;
  Twist twist;
};

/// trajectory_msgs/JointTrajectoryPoint: one waypoint, one value per joint in each list that is not empty.
struct TrajectoryPoint {
  std::vector<double> positions;      ///< [rad] or [m]
  std::vector<double> velocities;     ///< [rad/s] or [m/s]
  std::vector<double> accelerations;  ///< [rad/s^2] or [m/s^2]
  std::vector<double> effort;         ///< [N m] or [N]
  double time_from_start = 0;         ///< [s] after the trajectory's start
};

/// trajectory_msgs/JointTrajectory, an input: where named joints go, and when.
struct JointTrajectory {
  double stamp = 0;  ///< [s] sim time at which time_from_start counts from; 0 = at once
  std::vector<std::string> joint_names;
  std::vector<TrajectoryPoint> points;
};

/// control_msgs/JointTrajectoryControllerState (also FollowJointTrajectory's feedback): where a trajectory
/// controller wants its joints, where they are, and the difference, one value per joint.
struct JointTrajectoryControllerState {
  double stamp = 0;
  std::vector<std::string> joint_names;
  TrajectoryPoint desired;  ///< positions, velocities and accelerations
  TrajectoryPoint actual;   ///< positions and velocities
  TrajectoryPoint error;    ///< desired - actual: positions and velocities
};

/// std_msgs/Float64, an input: one command (a joint controller's position, velocity or effort).
struct Float64Command {
  double data = 0;
};

/// std_msgs/Float64MultiArray, an input: one command per joint of a group controller (its layout is not
/// read).
struct Float64ArrayCommand {
  std::vector<double> data;
};

/// std_msgs/Bool, an input (ros_control's emergency stop).
struct BoolCommand {
  bool data = false;
};

}  // namespace bullet_sim
