// The compatibility packages under compat/: their interfaces are the originals' (MD5 sums from the originals'
// definitions on Noetic: gazebo_msgs 2.9.2, controller_manager_msgs 0.20.0, control_msgs 1.5.2), and
// scripts/compat_packages.sh builds ours only where the system lacks the real package.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

// Every gazebo_msgs message and service.
#include <gazebo_msgs/ApplyBodyWrench.h>
#include <gazebo_msgs/ApplyJointEffort.h>
#include <gazebo_msgs/BodyRequest.h>
#include <gazebo_msgs/ContactState.h>
#include <gazebo_msgs/ContactsState.h>
#include <gazebo_msgs/DeleteLight.h>
#include <gazebo_msgs/DeleteModel.h>
#include <gazebo_msgs/GetJointProperties.h>
#include <gazebo_msgs/GetLightProperties.h>
#include <gazebo_msgs/GetLinkProperties.h>
#include <gazebo_msgs/GetLinkState.h>
#include <gazebo_msgs/GetModelProperties.h>
#include <gazebo_msgs/GetModelState.h>
#include <gazebo_msgs/GetPhysicsProperties.h>
#include <gazebo_msgs/GetWorldProperties.h>
#include <gazebo_msgs/JointRequest.h>
#include <gazebo_msgs/LinkState.h>
#include <gazebo_msgs/LinkStates.h>
#include <gazebo_msgs/ModelState.h>
#include <gazebo_msgs/ModelStates.h>
#include <gazebo_msgs/ODEJointProperties.h>
#include <gazebo_msgs/ODEPhysics.h>
#include <gazebo_msgs/PerformanceMetrics.h>
#include <gazebo_msgs/SensorPerformanceMetric.h>
#include <gazebo_msgs/SetJointProperties.h>
#include <gazebo_msgs/SetJointTrajectory.h>
#include <gazebo_msgs/SetLightProperties.h>
#include <gazebo_msgs/SetLinkProperties.h>
#include <gazebo_msgs/SetLinkState.h>
#include <gazebo_msgs/SetModelConfiguration.h>
#include <gazebo_msgs/SetModelState.h>
#include <gazebo_msgs/SetPhysicsProperties.h>
#include <gazebo_msgs/SpawnModel.h>
#include <gazebo_msgs/WorldState.h>

// Every controller_manager_msgs message and service.
#include <controller_manager_msgs/ControllerState.h>
#include <controller_manager_msgs/ControllerStatistics.h>
#include <controller_manager_msgs/ControllersStatistics.h>
#include <controller_manager_msgs/HardwareInterfaceResources.h>
#include <controller_manager_msgs/ListControllerTypes.h>
#include <controller_manager_msgs/ListControllers.h>
#include <controller_manager_msgs/LoadController.h>
#include <controller_manager_msgs/ReloadControllerLibraries.h>
#include <controller_manager_msgs/SwitchController.h>
#include <controller_manager_msgs/UnloadController.h>

// Every control_msgs message and service, and the messages of its actions.
#include <control_msgs/FollowJointTrajectoryAction.h>
#include <control_msgs/GripperCommand.h>
#include <control_msgs/GripperCommandAction.h>
#include <control_msgs/JointControllerState.h>
#include <control_msgs/JointJog.h>
#include <control_msgs/JointTolerance.h>
#include <control_msgs/JointTrajectoryAction.h>
#include <control_msgs/JointTrajectoryControllerState.h>
#include <control_msgs/PidState.h>
#include <control_msgs/PointHeadAction.h>
#include <control_msgs/QueryCalibrationState.h>
#include <control_msgs/QueryTrajectoryState.h>
#include <control_msgs/SingleJointPositionAction.h>

#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

template <class T>
std::string md5() {
  return ros::message_traits::MD5Sum<T>::value();
}
template <class T>
std::string serviceMd5() {
  return ros::service_traits::MD5Sum<T>::value();
}

TEST(GazeboMsgs, MessagesHaveTheOriginalsMd5Sums) {
  // Computed by genmsg from the .msg files of gazebo_msgs 2.9.2 (gazebo_ros_pkgs noetic-devel, f9e1a460).
  EXPECT_EQ(md5<gazebo_msgs::ContactState>(), "48c0ffb054b8c444f870cecea1ee50d9");
  EXPECT_EQ(md5<gazebo_msgs::ContactsState>(), "acbcb1601a8e525bf72509f18e6f668d");
  EXPECT_EQ(md5<gazebo_msgs::LinkState>(), "0818ebbf28ce3a08d48ab1eaa7309ebe");
  EXPECT_EQ(md5<gazebo_msgs::LinkStates>(), "48c080191eb15c41858319b4d8a609c2");
  EXPECT_EQ(md5<gazebo_msgs::ModelState>(), "9330fd35f2fcd82d457e54bd54e10593");
  EXPECT_EQ(md5<gazebo_msgs::ModelStates>(), "48c080191eb15c41858319b4d8a609c2");
  EXPECT_EQ(md5<gazebo_msgs::ODEJointProperties>(), "1b744c32a920af979f53afe2f9c3511f");
  EXPECT_EQ(md5<gazebo_msgs::ODEPhysics>(), "667d56ddbd547918c32d1934503dc335");
  EXPECT_EQ(md5<gazebo_msgs::PerformanceMetrics>(), "884f71fd5037b886ec5e126b83c4425a");
  EXPECT_EQ(md5<gazebo_msgs::SensorPerformanceMetric>(), "01762ded18cfe9ebc7c8222667c99547");
  EXPECT_EQ(md5<gazebo_msgs::WorldState>(), "de1a9de3ab7ba97ac0e9ec01a4eb481e");
}

TEST(GazeboMsgs, ServicesHaveTheOriginalsMd5Sums) {
  EXPECT_EQ(serviceMd5<gazebo_msgs::ApplyBodyWrench>(), "585b9f9618aa0581b207e2f2d90866bc");
  EXPECT_EQ(serviceMd5<gazebo_msgs::ApplyJointEffort>(), "c0039811b8cc919490b3cff748cdf46b");
  EXPECT_EQ(serviceMd5<gazebo_msgs::BodyRequest>(), "5eade9afe7f232d78005bd0cafeab755");
  EXPECT_EQ(serviceMd5<gazebo_msgs::DeleteLight>(), "ae11ea8100d536d5b92c2b5917abf912");
  EXPECT_EQ(serviceMd5<gazebo_msgs::DeleteModel>(), "9ce56b4e9e54616de25d796dc972a262");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetJointProperties>(), "7b30be900f50aa21efec4a0ec92d91c9");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetLightProperties>(), "df2cef87e13e2e6990e81e8aaa454c19");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetLinkProperties>(), "0e06a70386d0ee3fb880c02f23fcd821");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetLinkState>(), "09d6c98cce97b35f7ab9bd70300657ab");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetModelProperties>(), "5717f7bd34ed990fa80e28b3015027a3");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetModelState>(), "4c515e936d3319c9610c559c60bfc3d4");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetPhysicsProperties>(), "575a5e74786981b7df2e3afc567693a6");
  EXPECT_EQ(serviceMd5<gazebo_msgs::GetWorldProperties>(), "36bb0f2eccf4d8be971410c22818ba3f");
  EXPECT_EQ(serviceMd5<gazebo_msgs::JointRequest>(), "0be1351618e1dc030eb7959d9a4902de");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetJointProperties>(), "15a76e921b1410c698d82782ea5fa370");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetJointTrajectory>(), "88f5c10979e3f9649d5ae87a3b12aa65");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetLightProperties>(), "e6f13430c57278bb364aca53a1bf5ebf");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetLinkProperties>(), "d534ce1b36ee99de0ffa806c3a6348f0");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetLinkState>(), "8a5146eb66ae4d26b0860b08f3f271be");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetModelConfiguration>(), "10e3139d3b669c40afc057d38956fff7");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetModelState>(), "5b3ab0281d4f5445def017e3a2e4a07b");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SetPhysicsProperties>(), "97e2057080558ce4730434b5fae75c91");
  EXPECT_EQ(serviceMd5<gazebo_msgs::SpawnModel>(), "9ed9c82c96abe1a00c3e8cdaeee24413");
}

TEST(ControllerManagerMsgs, MessagesAndServicesHaveTheOriginalsMd5Sums) {
  // Computed by genmsg from controller_manager_msgs 0.20.0 (ros_control noetic-devel, 633c3746).
  EXPECT_EQ(md5<controller_manager_msgs::ControllerState>(), "aeb6b261d97793ab74099a3740245272");
  EXPECT_EQ(md5<controller_manager_msgs::ControllerStatistics>(), "697780c372c8d8597a1436d0e2ad3ba8");
  EXPECT_EQ(md5<controller_manager_msgs::ControllersStatistics>(), "a154c347736773e3700d1719105df29d");
  EXPECT_EQ(md5<controller_manager_msgs::HardwareInterfaceResources>(), "f25b55cbf1d1f76e82e5ec9e83f76258");
  EXPECT_EQ(serviceMd5<controller_manager_msgs::ListControllerTypes>(), "c1d4cd11aefa9f97ba4aeb5b33987f4e");
  EXPECT_EQ(serviceMd5<controller_manager_msgs::ListControllers>(), "1341feb2e63fa791f855565d0da950d8");
  EXPECT_EQ(serviceMd5<controller_manager_msgs::LoadController>(), "647e5c54b8d6468952d8d31f1efe96c0");
  EXPECT_EQ(serviceMd5<controller_manager_msgs::ReloadControllerLibraries>(),
            "40e8c411fd1797d2e2c486018f846040");
  EXPECT_EQ(serviceMd5<controller_manager_msgs::SwitchController>(), "b29a7abc673b2c54c14b54e50f8d06a5");
  EXPECT_EQ(serviceMd5<controller_manager_msgs::UnloadController>(), "647e5c54b8d6468952d8d31f1efe96c0");
  EXPECT_EQ(controller_manager_msgs::SwitchController::Request::BEST_EFFORT, 1);
  EXPECT_EQ(controller_manager_msgs::SwitchController::Request::STRICT, 2);
}

TEST(ControlMsgs, MessagesServicesAndActionsHaveTheOriginalsMd5Sums) {
  // Computed by genmsg (genaction for the actions) from control_msgs 1.5.2 (kinetic-devel, which Noetic
  // releases, 36e2e30).
  EXPECT_EQ(md5<control_msgs::GripperCommand>(), "680acaff79486f017132a7f198d40f08");
  EXPECT_EQ(md5<control_msgs::JointControllerState>(), "987ad85e4756f3aef7f1e5e7fe0595d1");
  EXPECT_EQ(md5<control_msgs::JointJog>(), "1685da700c8c2e1254afc92a5fb89c96");
  EXPECT_EQ(md5<control_msgs::JointTolerance>(), "f544fe9c16cf04547e135dd6063ff5be");
  EXPECT_EQ(md5<control_msgs::JointTrajectoryControllerState>(), "10817c60c2486ef6b33e97dcd87f4474");
  EXPECT_EQ(md5<control_msgs::PidState>(), "b138ec00e886c10e73f27e8712252ea6");
  EXPECT_EQ(md5<control_msgs::FollowJointTrajectoryAction>(), "bc4f9b743838566551c0390c65f1a248");
  EXPECT_EQ(md5<control_msgs::FollowJointTrajectoryGoal>(), "69636787b6ecbde4d61d711979bc7ecb");
  EXPECT_EQ(md5<control_msgs::FollowJointTrajectoryResult>(), "493383b18409bfb604b4e26c676401d2");
  EXPECT_EQ(md5<control_msgs::FollowJointTrajectoryFeedback>(), "10817c60c2486ef6b33e97dcd87f4474");
  EXPECT_EQ(md5<control_msgs::GripperCommandAction>(), "950b2a6ebe831f5d4f4ceaba3d8be01e");
  EXPECT_EQ(md5<control_msgs::JointTrajectoryAction>(), "a04ba3ee8f6a2d0985a6aeaf23d9d7ad");
  EXPECT_EQ(md5<control_msgs::PointHeadAction>(), "7252920f1243de1b741f14f214125371");
  EXPECT_EQ(md5<control_msgs::SingleJointPositionAction>(), "c4a786b7d53e5d0983decf967a5a779e");
  EXPECT_EQ(serviceMd5<control_msgs::QueryCalibrationState>(), "28af3beedcb84986b8e470dc5470507d");
  EXPECT_EQ(serviceMd5<control_msgs::QueryTrajectoryState>(), "ec93cdecbd8062d761aa52b7c90cd44b");
  EXPECT_EQ(control_msgs::FollowJointTrajectoryResult::GOAL_TOLERANCE_VIOLATED, -5);
}

// The build removes CATKIN_IGNORE where it builds ours, so `git status` shows it deleted: that deletion must
// never be committed, or a plain catkin_make would build our stand-ins over the real packages.
TEST(CompatPackages, EachCommitsItsCatkinIgnore) {
  const std::filesystem::path compat(COMPAT_DIR);
  if (!std::filesystem::exists(compat.parent_path() / ".git")) GTEST_SKIP() << "not a git checkout";
  for (const auto& package : std::filesystem::directory_iterator(compat)) {
    const auto listed = test::run("git -C " + compat.string() + " ls-tree --name-only HEAD " +
                                  package.path().filename().string() + "/CATKIN_IGNORE");
    EXPECT_THAT(listed.output, HasSubstr("CATKIN_IGNORE")) << package.path() << ": commit its CATKIN_IGNORE";
  }
}

/// A throw-away copy of compat/ and a folder for stand-in "real" packages.
class CompatPackagesScript : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = std::filesystem::temp_directory_path() /
            ("compat_test_" + std::to_string(::getpid()) + "_" +
             ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(root_);
    std::filesystem::create_directories(root_ / "real");
    std::filesystem::copy(std::string(COMPAT_DIR), root_ / "compat",
                          std::filesystem::copy_options::recursive);
    for (const auto& package : std::filesystem::directory_iterator(root_ / "compat")) {
      std::ofstream(package.path() / "CATKIN_IGNORE") << "committed\n";
    }
  }
  void TearDown() override { std::filesystem::remove_all(root_); }

  /// Runs the script over the copy with ROS_PACKAGE_PATH holding only the stand-ins.
  test::CommandResult runScript() {
    return test::run("ROS_PACKAGE_PATH=" + (root_ / "real").string() + " " + COMPAT_SCRIPT + " " +
                     (root_ / "compat").string() + " " + (root_ / "ws").string());
  }
  void addRealPackage(const std::string& name) {
    std::filesystem::create_directories(root_ / "real" / name);
    std::ofstream(root_ / "real" / name / "package.xml")
        << "<package format=\"2\"><name>" << name << "</name><version>9.9.9</version><description>real"
        << "</description><maintainer email=\"a@b.c\">a</maintainer><license>BSD</license></package>\n";
  }
  bool ignored(const std::string& name) const {
    return std::filesystem::exists(root_ / "compat" / name / "CATKIN_IGNORE");
  }

  std::filesystem::path root_;
};

/// Every compatibility package the repo ships, by folder name (each folder is named after its package).
std::vector<std::string> compatPackages() {
  std::vector<std::string> names;
  for (const auto& package : std::filesystem::directory_iterator(COMPAT_DIR)) {
    if (std::filesystem::exists(package.path() / "package.xml")) names.push_back(package.path().filename());
  }
  std::sort(names.begin(), names.end());
  return names;
}

TEST(CompatPackages, AreTheOnesTheDesignNames) {
  EXPECT_THAT(compatPackages(),
              ::testing::IsSupersetOf({"control_msgs", "controller_manager", "controller_manager_msgs",
                                       "gazebo_msgs", "joint_state_controller"}));
}

TEST_F(CompatPackagesScript, BuildsOursWhereTheSystemLacksTheRealPackage) {
  const auto result = runScript();
  ASSERT_EQ(result.status, 0) << result.errors;
  for (const auto& name : compatPackages()) {
    EXPECT_FALSE(ignored(name)) << name;
    EXPECT_THAT(result.output, HasSubstr("the system has no " + name + ";"));
  }
}

TEST_F(CompatPackagesScript, NeverShadowsARealPackage) {
  for (const auto& name : compatPackages()) {
    SCOPED_TRACE(name);
    addRealPackage(name);
    auto result = runScript();
    ASSERT_EQ(result.status, 0) << result.errors;
    EXPECT_TRUE(ignored(name));
    for (const auto& other : compatPackages()) {
      if (other == name) continue;
      EXPECT_FALSE(ignored(other)) << other << " is opted out with " << name;
    }

    // Opted in first, then the real package appears: ours is opted out again.
    std::filesystem::remove_all(root_ / "real" / name);
    ASSERT_EQ(runScript().status, 0);
    ASSERT_FALSE(ignored(name));
    addRealPackage(name);
    result = runScript();
    ASSERT_EQ(result.status, 0) << result.errors;
    EXPECT_TRUE(ignored(name));
    EXPECT_THAT(result.output, HasSubstr(name + " is installed at " + (root_ / "real").string()));
    std::filesystem::remove_all(root_ / "real" / name);
  }
}

}  // namespace
}  // namespace bullet_sim
