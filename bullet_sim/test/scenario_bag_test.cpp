// `scenario --bag` as a user runs it: a timeline run's bag is the same bytes on a rerun, compressed or not,
// and a run killed while it writes leaves a bag that `rosbag reindex` repairs, losing at most the chunk it
// had open.
#include <fcntl.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <rosbag/view.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "test_support.h"

extern char** environ;

namespace bullet_sim {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

/// This process's folder under the system's temporary folder, removed when the tests end.
const fs::path& scratchRoot() {
  struct Root {
    fs::path path = fs::temp_directory_path() / ("scenario_bag_test_" + std::to_string(getpid()));
    ~Root() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  };
  static const Root root;
  return root.path;
}

/// A fresh folder for a test's bags.
fs::path scratch(const std::string& name) {
  const fs::path dir = scratchRoot() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string scenarioFile(const std::string& name) { return test::fixture("scenarios/" + name); }

test::CommandResult runScenario(const std::string& arguments) {
  return test::run(std::string(SCENARIO) + " " + arguments + " 2>&1");
}

std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

TEST(ScenarioBag, ATimelineRunsBagIsTheSameBytesOnARerun) {
  const fs::path dir = scratch("rerun");
  for (const std::string compression : {"none", "lz4"}) {
    std::vector<std::string> bags;
    for (const std::string seed : {"3", "3", "4"}) {
      const fs::path out = dir / (compression + "_" + std::to_string(bags.size()));
      const auto run =
          runScenario(scenarioFile("reach_region.yaml") + " --seed " + seed + " --out " + out.string() +
                      " --bag --bag-compression " + compression + " --bag-chunk-size 100000");
      ASSERT_EQ(run.status, 0) << run.output;
      ASSERT_TRUE(fs::exists(out / "run.bag")) << run.output;
      EXPECT_FALSE(fs::exists(out / "run.bag.active"));
      bags.push_back(bytesOf(out / "run.bag"));
    }
    EXPECT_GT(bags[0].size(), compression == "none" ? 300000u : 100000u) << compression;
    EXPECT_TRUE(bags[0] == bags[1]) << compression << ": the same file and seed, the same bytes";
    EXPECT_FALSE(bags[0] == bags[2]) << compression << ": another seed, other lidar noise";
  }
}

/// A bag's chunks as its file lays them out: where each ends, and how many messages it holds (from the index
/// records after it). rosbag format 2.0: records of header length, header fields, data length, data.
struct ChunkLayout {
  uint64_t end = 0;
  uint64_t messages = 0;
};

std::vector<ChunkLayout> chunksOf(const std::string& bytes) {
  std::vector<ChunkLayout> chunks;
  size_t at = std::strlen("#ROSBAG V2.0\n");
  const auto u32 = [&](size_t offset) {
    uint32_t value;
    std::memcpy(&value, bytes.data() + offset, 4);
    return value;
  };
  while (at + 8 <= bytes.size()) {
    const uint32_t header_length = u32(at);
    std::map<std::string, std::string> fields;
    for (size_t field = at + 4; field < at + 4 + header_length;) {
      const uint32_t length = u32(field);
      const std::string text = bytes.substr(field + 4, length);
      fields[text.substr(0, text.find('='))] = text.substr(text.find('=') + 1);
      field += 4 + length;
    }
    const size_t data = at + 4 + header_length;
    const uint64_t end = data + 4 + u32(data);
    const char op = fields["op"].empty() ? 0 : fields["op"][0];
    if (op == 0x05) chunks.push_back({end, 0});  // a chunk, followed by an index record per connection in it
    if (op == 0x04 && !chunks.empty()) {
      uint32_t count;
      std::memcpy(&count, fields["count"].data(), 4);
      chunks.back().messages += count;
    }
    at = end;
  }
  return chunks;
}

struct Recorded {
  std::string topic;
  double time;
  std::vector<uint8_t> bytes;
  bool operator==(const Recorded& other) const {
    return topic == other.topic && time == other.time && bytes == other.bytes;
  }
};

std::vector<Recorded> messagesOf(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  std::vector<Recorded> found;
  for (const rosbag::MessageInstance& m : rosbag::View(bag)) {
    Recorded& recorded = found.emplace_back();
    recorded.topic = m.getTopic();
    recorded.time = m.getTime().toSec();
    recorded.bytes.resize(m.size());
    ros::serialization::OStream stream(recorded.bytes.data(), recorded.bytes.size());
    m.write(stream);
  }
  return found;
}

TEST(ScenarioBag, AKilledRunLeavesABagThatReindexRepairsLosingAtMostTheOpenChunk) {
  const fs::path dir = scratch("killed");
  const std::string chunk = "16384";
  const auto complete = runScenario(scenarioFile("circle_short.yaml") + " --out " + (dir / "whole").string() +
                                    " --bag --bag-chunk-size " + chunk);
  ASSERT_EQ(complete.status, 0) << complete.output;
  const std::string whole = (dir / "whole" / "run.bag").string();

  // The same run, five minutes long, killed once its bag holds a dozen chunks.
  const fs::path active = dir / "killed" / "run.bag.active";
  std::vector<std::string> words = {
      SCENARIO, scenarioFile("circle_long.yaml"), "--out", (dir / "killed").string(), "--bag",
      "--bag-chunk-size", chunk};
  std::vector<char*> argv;
  for (auto& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, SCENARIO, &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  const auto size = [&] {
    std::error_code missing;  // until the run opens it
    const auto bytes = fs::file_size(active, missing);
    return missing ? 0 : bytes;
  };
  while (size() < 12 * 16384 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // a poll of the file, not a synchronisation
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";
  const uint64_t written = size();
  ASSERT_GE(written, 12u * 16384) << "the bag did not grow within 30 s";

  const auto reindex = test::run("rosbag reindex -q " + active.string() + " 2>&1");
  ASSERT_EQ(reindex.status, 0) << reindex.output;
  // rosbag reads messages of one time in no particular order: the repaired bag must hold every message of the
  // whole one before its last time, and some of those at its last time (the rest were in the open chunk).
  std::vector<Recorded> repaired = messagesOf(active.string());
  std::vector<Recorded> expected = messagesOf(whole);
  ASSERT_FALSE(repaired.empty());
  const double last = repaired.back().time;
  ASSERT_LT(last, expected.back().time) << "circle_short.yaml must outlast the killed run";
  const auto at_last = [last](const Recorded& m) { return m.time == last; };
  std::vector<Recorded> expected_at_last;
  std::copy_if(expected.begin(), expected.end(), std::back_inserter(expected_at_last), at_last);
  expected.erase(
      std::remove_if(expected.begin(), expected.end(), [last](const Recorded& m) { return m.time >= last; }),
      expected.end());
  std::vector<Recorded> repaired_at_last;
  std::copy_if(repaired.begin(), repaired.end(), std::back_inserter(repaired_at_last), at_last);
  repaired.erase(std::remove_if(repaired.begin(), repaired.end(), at_last), repaired.end());
  ASSERT_EQ(repaired.size(), expected.size());
  for (size_t i = 0; i < repaired.size(); ++i) {
    ASSERT_TRUE(repaired[i] == expected[i]) << "message " << i << " (" << repaired[i].topic << ") differs";
  }
  for (const Recorded& message : repaired_at_last) {
    EXPECT_NE(std::find(expected_at_last.begin(), expected_at_last.end(), message), expected_at_last.end())
        << message.topic << " at " << last;
  }
  // The messages of the chunks surely closed when the run was killed: rosbag rewrites a chunk's header after
  // its data, so its data on disk is not enough; once the next chunk is whole on disk, it was closed.
  uint64_t closed = 0;
  const std::vector<ChunkLayout> chunks = chunksOf(bytesOf(whole));
  for (size_t k = 0; k + 1 < chunks.size(); ++k) {
    if (chunks[k + 1].end <= written) closed += chunks[k].messages;
  }
  EXPECT_GE(closed, 500u);
  EXPECT_GE(repaired.size() + repaired_at_last.size(), closed) << written << " bytes were on disk";
}

}  // namespace
}  // namespace bullet_sim
