// urdf_doctor: every defect of the seeds' own files (test/fixtures/doctor/, one per defect) is reported with
// its element, reason and fix; so is every case of test/fixtures/doctor/cases.yaml (issue 19 section 3:
// missing meshes and refused numbers do not stop the rest, mirrored wheel axes without a drive, joint ranges,
// NaN, zero, negative and absurd values); the exit codes keep their contract; the robots we ship come out
// clean.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <optional>
#include <string>
#include <vector>

#include "bullet_sim/doctor/doctor.h"
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

/// A finding that must be in the report exactly once: its severity, and parts of its message.
struct Finding {
  DoctorFinding::Severity severity;
  std::vector<std::string> parts;
};

/// One fixture per defect of a seed's file (test/fixtures/doctor/), and what urdf_doctor must say of it.
struct SeedDefect {
  std::string name;  ///< names the test case
  std::string fixture;
  int exit_code;                  ///< 0 clean or warnings only, 1 errors, 2 unreadable
  std::optional<size_t> errors;   ///< how many errors in all, where the others must not come
  std::vector<Finding> findings;  ///< each exactly once
};

class DoctorSeed : public ::testing::TestWithParam<SeedDefect> {};

TEST_P(DoctorSeed, IsReportedWithItsElementReasonAndFix) {
  const SeedDefect& defect = GetParam();
  const DoctorReport report = examine(defect.fixture);
  EXPECT_EQ(report.exitCode(), defect.exit_code) << report.text();
  if (defect.errors) {
    EXPECT_EQ(report.errors(), *defect.errors) << report.text();
  }
  for (const Finding& finding : defect.findings) {
    const auto matches = [&](const DoctorFinding& found) {
      return found.severity == finding.severity &&
             std::all_of(finding.parts.begin(), finding.parts.end(), [&](const std::string& part) {
               return found.message.find(part) != std::string::npos;
             });
    };
    EXPECT_EQ(std::count_if(report.findings.begin(), report.findings.end(), matches), 1)
        << finding.parts.front() << "\n"
        << report.text();
  }
}

const SeedDefect kSeedDefects[] = {
    {"Seed000FootprintOffsetSinksTheChairAndGivesTheHeight",
     "000_footprint_offset.urdf",
     1,
     std::nullopt,
     {{kError,
       {"joint [base_footprint_joint]", "link [front_left_link]) is 0.072836 m below [base_footprint]",
        "set its <origin> z to 0.60406 (now 0.53122)"}}}},
    {"Seed000ReversedRightWheelAxisSpinsTheChair",
     "000_reversed_right_axis.urdf",
     1,
     1,  // the left one is right
     {{kError,
       {"joint [front_right_joint]: turns about 0 -1 0", "joint [front_left_joint] turns about 0 1 0",
        "spins in place", "Fix: write <axis xyz=\"0 1 0\"/>"}}}},
    {"Seed000RevoluteLimitsOf180LookLikeDegrees",
     "000_caster_limits_in_degrees.urdf",
     1,
     1,  // its zero limits are on a joint nothing drives
     {{kError,
       {"joint [wheel_rear_right_joint] <limit>", "lower -180 and upper 180", "look like degrees",
        "make the joint continuous"}}}},
    {"Seed000LaserLinkReferenceAndFrameNameSuggestLaserCapitalL",
     "000_laser_link_reference.urdf",
     1,
     std::nullopt,
     {{kError, {"<gazebo reference=\"laser_link\"> names no link or joint (did you mean [laser_Link]?)"}},
      {kWarning,
       {"line 24: plugin [gazebo_rplidar] <frameName>laser_link</frameName>: names no link",
        "did you mean [laser_Link]?"}}}},
    {"Seed000UnexpandedMacroCallAndWhatItLeftOutAreBothReported",
     "000_unexpanded_macro.urdf",
     1,
     std::nullopt,
     {{kError, {"line 12: <mbot_base/> is not a URDF element", "write <xacro:mbot_base/>"}},
      {kError, {"urdfdom rejected the model", "parent link [base_link]"}}}},
    {"Seed000LidarOfSevenKilogramsIsDenserThanAnyMaterial",
     "000_lidar_mass.urdf",
     1,
     std::nullopt,
     {{kError,
       {"link [laser_Link] <inertial>: mass 6.8618 kg", "denser than any material",
        "a misplaced decimal point?"}}}},
    {"Seed001WheelCollisionRepeatingTheJointOriginIsFarFromItsVisual",
     "001_wheel_collision_origin.urdf",
     1,
     std::nullopt,
     {{kError,
       {"link [left_front_wheel] <collision>", "0.11587 m from its visual",
        "repeats the origin of joint [left_front_wheel_joint]",
        "give the collision the visual's <origin> (xyz 0 0 0)"}}}},
    {"Seed001UnitInertiaOnALightWheelIsAnError",
     "001_wheel_inertia.urdf",
     1,
     std::nullopt,
     {{kError,
       {"link [left_front_wheel] <inertial>: principal moments 1 1 1 kg m^2",
        "times off those of its collision shapes at 0.1 kg", "like a flywheel"}}}},
    {"Seed001CylinderCollisionUnderABoxVisualIsAWarning",
     "001_head_collision_shape.urdf",
     0,
     std::nullopt,
     {{kWarning,
       {"link [head] <collision>: it is a cylinder while its visual is a box",
        "use the visual's geometry"}}}},
    {"Seed001LostClosingTagIsAParseErrorWithLineColumnAndCause",
     "001_lost_closing_tags.urdf",
     2,
     std::nullopt,
     {{kError,
       {"line 6 column 5: <inertial> is closed by another element's closing tag, or not at all",
        "such as `inertial>`, is read as text", "close it with </inertial>"}}}},
    {"Seed002NonBreakingSpaceInATagIsAParseErrorWithLineAndColumn",
     "002_non_breaking_space.urdf",
     2,
     std::nullopt,
     {{kError,
       {"line 6 column 14: XML cannot be parsed", "non-breaking space (U+00A0",
        "replace it with a plain space"}}}},
    {"Seed003BothReversedRightWheelsOfTheSkidSteerAreReported",
     "003_reversed_right_axes.urdf",
     1,
     2,
     {{kError, {"joint [yq_Joint]: turns about 0 -1 0", "plugin [skid_steer_drive_controller]"}},
      {kError, {"joint [yh_Joint]: turns about 0 -1 0", "plugin [skid_steer_drive_controller]"}}}},
    {"Seed003ZeroEffortAndVelocityOnThePanTiltItDrives",
     "003_zero_limits.urdf",
     1,
     4,  // the loader's refusal, and the doctor's detail, for each joint
     {{kError, {"joint [jq1_Joint] <limit>", "effort and velocity are 0, yet a plugin drives it"}},
      {kError, {"joint [jq2_Joint] <limit>", "effort and velocity are 0, yet a plugin drives it"}},
      {kError, {"plugin [pan_tilt] joint [jq1_Joint] has no effort limit"}},
      {kError, {"plugin [pan_tilt] joint [jq2_Joint] has no effort limit"}}}},
};

INSTANTIATE_TEST_SUITE_P(Fixtures, DoctorSeed, ::testing::ValuesIn(kSeedDefects),
                         [](const ::testing::TestParamInfo<SeedDefect>& info) { return info.param.name; });

/// A row of test/fixtures/doctor/cases.yaml (its header says what each field means).
struct DoctorCase {
  std::string file;
  int exit_code = 0;
  std::vector<std::string> said;
  std::optional<size_t> errors;
  std::optional<size_t> warnings;
  std::string table_error;  ///< why the table could not be read: the one case then fails with it
};

std::vector<DoctorCase> loadDoctorCases() {
  std::vector<DoctorCase> cases;
  try {
    for (const YAML::Node& node : YAML::LoadFile(fixture("doctor/cases.yaml"))) {
      DoctorCase c;
      c.file = node["file"].as<std::string>();
      c.exit_code = node["exit"].as<int>();
      c.said = node["said"].as<std::vector<std::string>>(std::vector<std::string>());
      if (node["errors"]) c.errors = node["errors"].as<size_t>();
      if (node["warnings"]) c.warnings = node["warnings"].as<size_t>();
      cases.push_back(c);
    }
  } catch (const std::exception& error) {
    cases = {DoctorCase{"cases.yaml", 0, {}, {}, {}, error.what()}};
  }
  return cases;
}

class DoctorTable : public ::testing::TestWithParam<DoctorCase> {};

TEST_P(DoctorTable, GivesItsExitCodeAndFindings) {
  const DoctorCase& c = GetParam();
  ASSERT_EQ(c.table_error, "");
  const DoctorReport report = examine(c.file);
  EXPECT_EQ(report.exitCode(), c.exit_code) << report.text();
  if (c.errors) {
    EXPECT_EQ(report.errors(), *c.errors) << report.text();
  }
  if (c.warnings) {
    EXPECT_EQ(report.warnings(), *c.warnings) << report.text();
  }
  for (const std::string& part : c.said) {
    const auto count =
        std::count_if(report.findings.begin(), report.findings.end(),
                      [&](const DoctorFinding& f) { return f.message.find(part) != std::string::npos; });
    EXPECT_EQ(count, 1) << part << "\n" << report.text();
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, DoctorTable, ::testing::ValuesIn(loadDoctorCases()),
                         [](const ::testing::TestParamInfo<DoctorCase>& info) {
                           std::string name = info.param.file.substr(0, info.param.file.find('.'));
                           std::replace_if(
                               name.begin(), name.end(), [](char c) { return !std::isalnum(c); }, '_');
                           return name;
                         });

TEST(DoctorSeed002, NonBreakingSpaceBetweenElementsIsAWarningWithLineAndColumn) {
  const std::string urdf = readFile(fixture("robots/minimal.urdf"));
  const auto at = urdf.find("<link");
  const DoctorReport report = examineUrdf(urdf.substr(0, at) + "\xC2\xA0" + urdf.substr(at), "pasted.urdf",
                                          PackageResolver::fromEnvironment());
  EXPECT_EQ(report.exitCode(), 0) << report.text();
  EXPECT_EQ(countFindings(report, kWarning, {"line 4 column 3: holds a non-breaking space (U+00A0"}), 1u)
      << report.text();
}

TEST(Doctor, ATextWithoutAnyElementIsUnreadable) {  // found by scripts/fuzz.sh
  const DoctorReport report = examineUrdf("<?xml version=\"1.0\"?>\n<!-- a comment only -->\n",
                                          "comment.urdf", PackageResolver::fromEnvironment());
  EXPECT_EQ(report.exitCode(), 2) << report.text();
  EXPECT_EQ(countFindings(report, kError, {"the file: holds no XML element"}), 1u) << report.text();
}

TEST(Doctor, MassLessMovingLinkAndMissingMeshComeFromTheLoader) {
  EXPECT_EQ(countFindings(examine("massless_moving_link.urdf"), kWarning,
                          {"link [wheel]: it has no mass; it is simulated as a solid box of 0.01 kg"}),
            1u);
  const DoctorReport mesh = examineUrdf(readFile(fixture("robots/fail_missing_mesh.urdf")),
                                        "fail_missing_mesh.urdf", PackageResolver::fromEnvironment());
  EXPECT_EQ(
      countFindings(mesh, kError, {"link [base_link] <collision>: cannot load mesh", "no_such_mesh.stl"}), 1u)
      << mesh.text();
}

struct ShippedRobot {
  std::string package;
  std::string xacro;
  std::vector<std::string> args;               ///< xacro's name:=value arguments
  std::vector<std::string> expected_warnings;  ///< a part of each warning that stays, and why in the docs
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
        ShippedRobot{"tianracer_description", "urdf/tianracer.urdf.xacro", {}, {}},
        // The multi-sensor test robot: a bumper's frameName world is a global frame; hector's own-type
        // services are left out.
        ShippedRobot{"bullet_sim",
                     "test/fixtures/robots/multi_sensor_robot.urdf.xacro",
                     {"drive:=force_based"},
                     {"[imu/data/set_accel_bias] and [imu/data/set_rate_bias] services",
                      "[navsat/fix/set_reference_geopose] service"}}));

/// urdf_doctor's exit status and what it prints, run as a user would.
test::CommandResult doctor(const std::string& arguments) {
  test::CommandResult result = test::run(std::string(URDF_DOCTOR) + " " + arguments);
  return result;
}

/// urdf_doctor run as a user would, on a file shipped in `package` (none: `file` as it is), and what it must
/// say.
struct ToolRun {
  std::string name;  ///< names the test case
  std::string package;
  std::string file;
  std::string arguments;  ///< after the file
  int exit_code;
  std::vector<std::string> said;  ///< parts of its output
};

class DoctorTool : public ::testing::TestWithParam<ToolRun> {};

TEST_P(DoctorTool, ExitsWithItsCodeAndSaysWhy) {
  const ToolRun& run = GetParam();
  const std::string file = run.package.empty() ? run.file : test::packageFile(run.package, run.file);
  const auto result = doctor(file + " " + run.arguments);
  EXPECT_EQ(result.status, run.exit_code) << result.output << result.errors;
  for (const auto& part : run.said) EXPECT_THAT(result.output, HasSubstr(part));
}

const ToolRun kToolRuns[] = {
    {"ZeroOnAShippedXacro",
     "smartcar_description",
     "urdf/smartcar.urdf.xacro",
     "with_lidar:=false",
     0,
     {"smartcar.urdf.xacro: clean"}},
    {"ZeroOnWarningsOnly",
     "bullet_sim",
     "test/fixtures/doctor/001_head_collision_shape.urdf",
     "",
     0,
     {"0 errors, 1 warning"}},
    {"OneOnWarningsThatCountAsErrors",
     "bullet_sim",
     "test/fixtures/doctor/warning_only_absurd_rate.urdf",
     "--warnings-as-errors",
     1,
     {"warning: plugin [drive]: update rate 1e+06 Hz", "0 errors, 1 warning"}},
    {"ZeroOnACleanFileWhenWarningsCountAsErrors",
     "bullet_sim",
     "test/fixtures/doctor/clean_two_wheeler.urdf",
     "--warnings-as-errors",
     0,
     {"clean_two_wheeler.urdf: clean"}},
    {"OneOnErrorsWithMissingMeshesAndTheRest",
     "bullet_sim",
     "test/fixtures/doctor/missing_meshes_and_other_faults.urdf",
     "",
     1,
     {"no_such_wheel.stl", "<samples> must be > 0, not 0", "lower and upper are both 0.5"}},
    {"OneAndEveryProblem",
     "bullet_sim",
     "test/fixtures/robots/fail_two_problems.urdf",
     "",
     1,
     {"error: link [base_link] <inertial>: mass -1 kg is not positive", "no_such_mesh.stl", "2 errors"}},
    {"TwoOnAParseError",
     "bullet_sim",
     "test/fixtures/doctor/002_non_breaking_space.urdf",
     "",
     2,
     {"line 6 column 14"}},
    {"TwoWithXacrosMessageWhenXacroFails",
     "bullet_sim",
     "test/fixtures/doctor/fail_xacro.urdf.xacro",
     "",
     2,
     {"fail_xacro.urdf.xacro failed: error: name 'undefined_base_name' is not defined"}},
    {"TwoOnAFileThatCannotBeRead",
     "",
     "/nonexistent/robot.urdf",
     "",
     2,
     {"/nonexistent/robot.urdf: error: the file cannot be read"}},
    {"TwoOnAFolder", "bullet_sim", "test/fixtures/doctor", "--warnings-as-errors", 2, {"not readable"}},
};

INSTANTIATE_TEST_SUITE_P(Exits, DoctorTool, ::testing::ValuesIn(kToolRuns),
                         [](const ::testing::TestParamInfo<ToolRun>& info) { return info.param.name; });

TEST(DoctorToolUsage, NoFileIsAUsageError) { EXPECT_EQ(doctor("").status, 2); }

}  // namespace
}  // namespace bullet_sim
