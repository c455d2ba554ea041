// urdf_doctor calls each plugin's own check through the registry (PluginType::check): the diff drive's check
// finds its reversed wheel and a zero limit on a wheel, a registry without that check finds neither, and what
// a registered check returns is reported as the doctor's own, once per element.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "bullet_sim/doctor/doctor.h"
#include "bullet_sim/plugins/registry.h"
#include "test_support.h"

namespace bullet_sim {
namespace {

using test::fixture;
using test::readFile;

constexpr char kDiffDrive[] = "libgazebo_ros_diff_drive.so";

/// The clean two-wheeler (a diff drive named [drive]) with `edit` applied to its joint `name`.
template <class Edit>
std::string withJoint(const std::string& name, Edit edit) {
  return test::editUrdf(readFile(fixture("doctor/clean_two_wheeler.urdf")), [&](tinyxml2::XMLElement& robot) {
    for (auto* joint = robot.FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
      if (joint->Attribute("name", name.c_str())) edit(*joint);
    }
  });
}

std::string reversedRightWheel() {
  return withJoint("right_wheel_joint", [](tinyxml2::XMLElement& joint) {
    joint.FirstChildElement("axis")->SetAttribute("xyz", "0 -1 0");
  });
}

std::string zeroEffortOnLeftWheel() {
  return withJoint("left_wheel_joint", [](tinyxml2::XMLElement& joint) {
    auto* limit = joint.InsertNewChildElement("limit");
    limit->SetAttribute("effort", "0");
    limit->SetAttribute("velocity", "5");
  });
}

/// The built-in registry with the diff drive's check replaced by `check` (nullptr: it has none).
PluginRegistry withDiffDriveCheck(PluginCheck check) {
  PluginRegistry registry = PluginRegistry::builtin();
  PluginType type = *registry.find(kDiffDrive, nullptr);
  type.check = std::move(check);
  registry.add(std::move(type));
  return registry;
}

DoctorReport examine(const std::string& urdf, const PluginRegistry& registry = PluginRegistry::builtin()) {
  return examineUrdf(urdf, "two_wheeler", PackageResolver::fromEnvironment(), Limits(), registry);
}

size_t saying(const DoctorReport& report, const std::string& part) {
  return std::count_if(report.findings.begin(), report.findings.end(), [&](const DoctorFinding& finding) {
    return finding.message.find(part) != std::string::npos;
  });
}

const std::string kReversed =
    "joint [right_wheel_joint]: turns about 0 -1 0, backwards (-y) in [base_link], "
    "while joint [left_wheel_joint] turns about 0 1 0: plugin [drive] then turns them against each other";
const std::string kZeroEffort = "joint [left_wheel_joint] <limit>: its effort is 0, yet a plugin drives it";

TEST(DoctorPluginChecks, TheDiffDrivesCheckFindsItsReversedWheel) {
  const DoctorReport report = examine(reversedRightWheel());
  EXPECT_EQ(report.errors(), 1u) << report.text();
  EXPECT_EQ(saying(report, kReversed), 1u) << report.text();
}

TEST(DoctorPluginChecks, TheDiffDrivesCheckFindsAZeroEffortOnItsWheel) {
  const DoctorReport report = examine(zeroEffortOnLeftWheel());
  EXPECT_EQ(saying(report, kZeroEffort), 1u) << report.text();
}

TEST(DoctorPluginChecks, WithoutTheDiffDrivesCheckNeitherIsFound) {
  // The doctor's own mirrored-wheel check leaves a drive's wheels to the drive: both findings were its
  // check's.
  const PluginRegistry registry = withDiffDriveCheck(nullptr);
  const DoctorReport reversed = examine(reversedRightWheel(), registry);
  EXPECT_EQ(reversed.errors(), 0u) << reversed.text();  // the parser's warning that it compensates remains
  EXPECT_EQ(saying(reversed, kReversed), 0u) << reversed.text();
  const DoctorReport zero = examine(zeroEffortOnLeftWheel(), registry);
  EXPECT_EQ(saying(zero, "<limit>: its effort is 0"), 0u) << zero.text();
}

TEST(DoctorPluginChecks, ARegisteredChecksFindingsAreReportedOncePerElement) {
  std::vector<std::string> called;
  const PluginRegistry registry = withDiffDriveCheck([&](const PluginCheckInput& input) {
    called.push_back(input.declaration.name + " of " + input.model.name + ", zero limits: " +
                     std::to_string(input.zero_limits.size()));
    return std::vector<PluginFinding>{{false, "joint [left_wheel_joint]", "first about the left wheel"},
                                      {true, "joint [left_wheel_joint]", "second about the left wheel"},
                                      {true, "link [base_link]", "about the base"}};
  });
  const DoctorReport report = examine(readFile(fixture("doctor/clean_two_wheeler.urdf")), registry);
  EXPECT_EQ(called, std::vector<std::string>{"drive of clean_two_wheeler, zero limits: 0"});
  ASSERT_EQ(report.findings.size(), 2u) << report.text();
  EXPECT_EQ(report.findings[0].severity, DoctorFinding::Severity::kWarning);
  EXPECT_EQ(report.findings[0].message, "first about the left wheel");
  EXPECT_EQ(report.findings[1].severity, DoctorFinding::Severity::kError);
  EXPECT_EQ(report.findings[1].message, "about the base");
}

}  // namespace
}  // namespace bullet_sim
