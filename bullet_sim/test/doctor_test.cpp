// urdf_doctor: every defect of the seeds' own files (test/fixtures/doctor/, one per defect) is reported with
// its element, reason and fix; the exit codes keep their contract; the robots we ship come out clean.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <string>

#include "bullet_sim/tools/doctor.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using ::testing::HasSubstr;

using test::fixture;
using test::readFile;

DoctorReport examine(const std::string& file) {
  return examineUrdf(readFile(fixture("doctor/" + file)), file, PackageResolver::fromEnvironment());
}

/// The findings of `severity` that contain every one of `parts`.
size_t countFindings(const DoctorReport& report, DoctorFinding::Severity severity,
                     std::initializer_list<std::string> parts) {
  return std::count_if(report.findings.begin(), report.findings.end(), [&](const DoctorFinding& finding) {
    return finding.severity == severity &&
           std::all_of(parts.begin(), parts.end(), [&](const std::string& part) {
             return finding.message.find(part) != std::string::npos;
           });
  });
}

constexpr auto kError = DoctorFinding::Severity::kError;
constexpr auto kWarning = DoctorFinding::Severity::kWarning;

TEST(DoctorSeed000, FootprintOffsetSinksTheChairAndGivesTheHeight) {
  const DoctorReport report = examine("000_footprint_offset.urdf");
  EXPECT_EQ(report.exitCode(), 1) << report.text();
  EXPECT_EQ(countFindings(report, kError,
                          {"joint [base_footprint_joint]",
                           "link [front_left_link]) is 0.072836 m below [base_footprint]",
                           "set its <origin> z to 0.60406 (now 0.53122)"}),
            1u)
      << report.text();
}

TEST(DoctorSeed000, ReversedRightWheelAxisSpinsTheChair) {
  const DoctorReport report = examine("000_reversed_right_axis.urdf");
  EXPECT_EQ(report.exitCode(), 1) << report.text();
  EXPECT_EQ(countFindings(report, kError,
                          {"joint [front_right_joint]: turns about 0 -1 0",
                           "joint [front_left_joint] turns about 0 1 0", "spins in place",
                           "Fix: write <axis xyz=\"0 1 0\"/>"}),
            1u)
      << report.text();
  EXPECT_EQ(report.errors(), 1u) << "the left wheel is right: " << report.text();
}

TEST(DoctorSeed000, RevoluteLimitsOf180LookLikeDegrees) {
  const DoctorReport report = examine("000_caster_limits_in_degrees.urdf");
  EXPECT_EQ(countFindings(report, kError,
                          {"joint [wheel_rear_right_joint] <limit>", "lower -180 and upper 180",
                           "look like degrees", "make the joint continuous"}),
            1u)
      << report.text();
  EXPECT_EQ(report.errors(), 1u) << "its zero limits are on a joint nothing drives: " << report.text();
}

TEST(DoctorSeed000, LaserLinkReferenceAndFrameNameSuggestLaserCapitalL) {
  const DoctorReport report = examine("000_laser_link_reference.urdf");
  EXPECT_EQ(countFindings(
                report, kError,
                {"<gazebo reference=\"laser_link\"> names no link or joint (did you mean [laser_Link]?)"}),
            1u)
      << report.text();
  EXPECT_EQ(
      countFindings(report, kError,
                    {"line 24: plugin [gazebo_rplidar] <frameName>laser_link</frameName>: names no link",
                     "did you mean [laser_Link]?"}),
      1u)
      << report.text();
}

TEST(DoctorSeed000, UnexpandedMacroCallAndWhatItLeftOutAreBothReported) {
  const DoctorReport report = examine("000_unexpanded_macro.urdf");
  EXPECT_EQ(report.exitCode(), 1) << report.text();
  EXPECT_EQ(countFindings(report, kError,
                          {"line 12: <mbot_base/> is not a URDF element", "write <xacro:mbot_base/>"}),
            1u)
      << report.text();
  EXPECT_EQ(countFindings(report, kError, {"urdfdom rejected the model", "parent link [base_link]"}), 1u)
      << report.text();
}

TEST(DoctorSeed000, LidarOfSevenKilogramsIsDenserThanAnyMaterial) {
  const DoctorReport report = examine("000_lidar_mass.urdf");
  EXPECT_EQ(countFindings(report, kError,
                          {"link [laser_Link] <inertial>: mass 6.8618 kg", "denser than any material",
                           "a misplaced decimal point?"}),
            1u)
      << report.text();
}

TEST(DoctorSeed001, WheelCollisionRepeatingTheJointOriginIsFarFromItsVisual) {
  const DoctorReport report = examine("001_wheel_collision_origin.urdf");
  EXPECT_EQ(report.exitCode(), 1) << report.text();
  EXPECT_EQ(countFindings(report, kError,
                          {"link [left_front_wheel] <collision>", "0.11587 m from its visual",
                           "repeats the origin of joint [left_front_wheel_joint]",
                           "give the collision the visual's <origin> (xyz 0 0 0)"}),
            1u)
      << report.text();
}

TEST(DoctorSeed001, UnitInertiaOnALightWheelIsAnError) {
  const DoctorReport report = examine("001_wheel_inertia.urdf");
  EXPECT_EQ(countFindings(report, kError,
                          {"link [left_front_wheel] <inertial>: principal moments 1 1 1 kg m^2",
                           "times off those of its collision shapes at 0.1 kg", "like a flywheel"}),
            1u)
      << report.text();
}

TEST(DoctorSeed001, CylinderCollisionUnderABoxVisualIsAWarning) {
  const DoctorReport report = examine("001_head_collision_shape.urdf");
  EXPECT_EQ(report.exitCode(), 0) << report.text();
  EXPECT_EQ(countFindings(report, kWarning,
                          {"link [head] <collision>: it is a cylinder while its visual is a box",
                           "use the visual's geometry"}),
            1u)
      << report.text();
}

TEST(DoctorSeed001, LostClosingTagIsAParseErrorWithLineColumnAndCause) {
  const DoctorReport report = examine("001_lost_closing_tags.urdf");
  EXPECT_EQ(report.exitCode(), 2) << report.text();
  EXPECT_EQ(
      countFindings(report, kError,
                    {"line 6 column 5: <inertial> is closed by another element's closing tag, or not at all",
                     "such as `inertial>`, is read as text", "close it with </inertial>"}),
      1u)
      << report.text();
}

TEST(DoctorSeed002, NonBreakingSpaceInATagIsAParseErrorWithLineAndColumn) {
  const DoctorReport report = examine("002_non_breaking_space.urdf");
  EXPECT_FALSE(report.readable);
  EXPECT_EQ(report.exitCode(), 2);
  EXPECT_EQ(countFindings(report, kError,
                          {"line 6 column 14: XML cannot be parsed", "non-breaking space (U+00A0",
                           "replace it with a plain space"}),
            1u)
      << report.text();
}

TEST(DoctorSeed002, NonBreakingSpaceBetweenElementsIsAWarningWithLineAndColumn) {
  const std::string urdf = readFile(fixture("robots/minimal.urdf"));
  const auto at = urdf.find("<link");
  const DoctorReport report = examineUrdf(urdf.substr(0, at) + "\xC2\xA0" + urdf.substr(at), "pasted.urdf",
                                          PackageResolver::fromEnvironment());
  EXPECT_EQ(report.exitCode(), 0) << report.text();
  EXPECT_EQ(countFindings(report, kWarning, {"line 4 column 3: holds a non-breaking space (U+00A0"}), 1u)
      << report.text();
}

TEST(DoctorSeed003, BothReversedRightWheelsOfTheSkidSteerAreReported) {
  const DoctorReport report = examine("003_reversed_right_axes.urdf");
  EXPECT_EQ(report.errors(), 2u) << report.text();
  for (const char* joint : {"joint [yq_Joint]: turns about 0 -1 0", "joint [yh_Joint]: turns about 0 -1 0"})
    EXPECT_EQ(countFindings(report, kError, {joint, "plugin [skid_steer_drive_controller]"}), 1u)
        << report.text();
}

TEST(DoctorSeed003, ZeroEffortAndVelocityOnThePanTiltItDrives) {
  const DoctorReport report = examine("003_zero_limits.urdf");
  EXPECT_EQ(report.errors(), 4u) << report.text();  // the loader's refusal, and the doctor's detail
  for (const char* joint : {"jq1_Joint", "jq2_Joint"}) {
    const std::string name = joint;
    EXPECT_EQ(
        countFindings(report, kError,
                      {"joint [" + name + "] <limit>", "effort and velocity are 0, yet a plugin drives it"}),
        1u)
        << report.text();
    EXPECT_EQ(countFindings(report, kError, {"plugin [pan_tilt] joint [" + name + "] has no effort limit"}),
              1u)
        << report.text();
  }
}

TEST(Doctor, ATextWithoutAnyElementIsUnreadable) {  // found by scripts/fuzz.sh
  const DoctorReport report = examineUrdf("<?xml version=\"1.0\"?>\n<!-- a comment only -->\n",
                                          "comment.urdf", PackageResolver::fromEnvironment());
  EXPECT_EQ(report.exitCode(), 2) << report.text();
  EXPECT_EQ(countFindings(report, kError, {"the file: holds no XML element"}), 1u) << report.text();
}

TEST(Doctor, MassLessMovingLinkAndMissingMeshComeFromTheLoader) {
  EXPECT_EQ(countFindings(examine("massless_moving_link.urdf"), kError,
                          {"link [wheel] moves on joint [wheel_joint] but has no mass"}),
            1u);
  const DoctorReport mesh = examineUrdf(readFile(fixture("robots/fail_missing_mesh.urdf")),
                                        "fail_missing_mesh.urdf", PackageResolver::fromEnvironment());
  EXPECT_EQ(countFindings(mesh, kError, {"link [base_link] <visual>: cannot load mesh", "no_such_mesh.stl"}),
            1u)
      << mesh.text();
}

struct ShippedRobot {
  std::string package;
  std::string xacro;
  std::vector<std::string> args;               ///< xacro's name:=value arguments
  std::vector<std::string> expected_warnings;  ///< a part of each warning that stays, and why in the README
};

class DoctorShipped : public ::testing::TestWithParam<ShippedRobot> {};

TEST_P(DoctorShipped, IsCleanButForKnownWarnings) {
  const ShippedRobot& robot = GetParam();
  const DoctorReport report = examineUrdf(test::expandXacro(robot.package, robot.xacro, robot.args),
                                          robot.xacro, PackageResolver::fromEnvironment());
  EXPECT_EQ(report.exitCode(), 0) << report.text();
  EXPECT_EQ(report.warnings(), robot.expected_warnings.size()) << report.text();
  for (const auto& warning : robot.expected_warnings)
    EXPECT_EQ(countFindings(report, kWarning, {warning}), 1u) << report.text();
}

INSTANTIATE_TEST_SUITE_P(
    Robots, DoctorShipped,
    ::testing::Values(
        // The lidar keeps the CAD export's inertia (puck and bracket), scaled to its
        // mass; its collision is only the puck, about 14 times lighter in rotation.
        ShippedRobot{"smartwheelchair_model",
                     "urdf/smartwheelchair_model.urdf.xacro",
                     {},
                     {"link [laser_Link] <inertial>: principal moments"}},
        ShippedRobot{"smartcar_description", "urdf/smartcar.urdf.xacro", {}, {}},
        ShippedRobot{"smartcar_description", "urdf/smartcar.urdf.xacro", {"with_lidar:=false"}, {}},
        ShippedRobot{"yahboomcar_description", "urdf/yahboomcar.urdf.xacro", {}, {}},
        ShippedRobot{"tianracer_description", "urdf/tianracer.urdf.xacro", {}, {}}));

/// urdf_doctor's exit status and what it prints, run as a user would.
test::CommandResult doctor(const std::string& arguments) {
  test::CommandResult result = test::run(std::string(URDF_DOCTOR) + " " + arguments);
  return result;
}

TEST(DoctorTool, ExitsZeroOnAShippedXacro) {
  const auto result =
      doctor(test::packageFile("smartcar_description", "urdf/smartcar.urdf.xacro") + " with_lidar:=false");
  EXPECT_EQ(result.status, 0) << result.output << result.errors;
  EXPECT_THAT(result.output, HasSubstr("smartcar.urdf.xacro: clean"));
}

TEST(DoctorTool, ExitsZeroOnWarningsOnly) {
  const auto result = doctor(fixture("doctor/001_head_collision_shape.urdf"));
  EXPECT_EQ(result.status, 0) << result.output;
  EXPECT_THAT(result.output, HasSubstr("0 errors, 1 warning"));
}

TEST(DoctorTool, ExitsOneAndListsEveryProblem) {
  const auto result = doctor(fixture("robots/fail_two_problems.urdf"));
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_THAT(result.output, HasSubstr("error: link [base_link] <inertial>: mass -1 kg is not positive"));
  EXPECT_THAT(result.output, HasSubstr("no_such_mesh.stl"));
  EXPECT_THAT(result.output, HasSubstr("2 errors"));
}

TEST(DoctorTool, ExitsTwoOnAParseError) {
  const auto result = doctor(fixture("doctor/002_non_breaking_space.urdf"));
  EXPECT_EQ(result.status, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr("line 6 column 14"));
}

TEST(DoctorTool, ExitsTwoWithXacrosMessageWhenXacroFails) {
  const auto result = doctor(fixture("doctor/fail_xacro.urdf.xacro"));
  EXPECT_EQ(result.status, 2) << result.output;
  EXPECT_THAT(result.output,
              HasSubstr("fail_xacro.urdf.xacro failed: error: name 'undefined_base_name' is not "
                        "defined"));
}

TEST(DoctorTool, ExitsTwoOnAFileThatCannotBeRead) {
  const auto result = doctor("/nonexistent/robot.urdf");
  EXPECT_EQ(result.status, 2) << result.output;
  EXPECT_THAT(result.output, HasSubstr("/nonexistent/robot.urdf: error: cannot read the file"));
  EXPECT_EQ(doctor("").status, 2) << "no file is a usage error";
}

}  // namespace
}  // namespace bullet_sim
