// Item 5 of issue 12: unsafe writes (predictable temporaries, device and FIFO targets
// replaced, modes lost, temporaries of killed writers left forever).
#include <grp.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <clothlab/io/atomic_file.hpp>
#include <clothlab/process/isolation.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "../support/read_text.hpp"

namespace {

namespace fs = std::filesystem;
using clothlab::io::check_output_path;
using clothlab::io::remove_stale_temporaries;
using clothlab::io::write_file_atomically;
using clothlab::io::WriteError;

using clothlab::testing::read_text;

class AtomicFile : public testing::Test {
 protected:
  void SetUp() override {
    folder_ =
        fs::temp_directory_path() / ("clothlab_io_" + std::to_string(getpid()) + "_" +
                                     testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }

  std::vector<std::string> names() const {
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(folder_))
      found.push_back(entry.path().filename().string());
    std::sort(found.begin(), found.end());
    return found;
  }

  fs::path folder_;
};

// The message names the target and the reason; what() is one line.
std::string message_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const WriteError& error) {
    return error.what();
  }
  return "(no error)";
}

TEST_F(AtomicFile, WritesTheWholeFileAndLeavesNoTemporary) {
  write_file_atomically(folder_ / "out.json", std::string_view("{}\n"));
  write_file_atomically(folder_ / "out.json", [](std::ostream& out) { out << "{\"a\": 1}\n"; });
  EXPECT_EQ(read_text(folder_ / "out.json"), "{\"a\": 1}\n");
  EXPECT_EQ(names(), std::vector<std::string>{"out.json"});
}

// A file given as pieces (a .vtp: XML, array headers, arrays where they lie) is their
// concatenation, empty pieces and more pieces than one writev() takes included.
TEST_F(AtomicFile, PiecesAreWrittenOneAfterAnother) {
  std::vector<std::string> texts;
  std::string expected;
  for (int i = 0; i < 200; ++i) {
    texts.push_back(i % 7 == 0 ? std::string() : std::string(static_cast<size_t>(i), 'a' + i % 26));
    expected += texts.back();
  }
  texts.push_back(std::string(3 << 20, 'z'));  // larger than a pipe or page, one piece
  expected += texts.back();
  const std::vector<std::string_view> pieces(texts.begin(), texts.end());
  write_file_atomically(folder_ / "pieces.bin", pieces, clothlab::io::Durability::Renamed);
  EXPECT_EQ(read_text(folder_ / "pieces.bin"), expected);
  EXPECT_EQ(names(), std::vector<std::string>{"pieces.bin"});
}

// Without fsync (frames) the same guarantees hold for readers and a killed writer: a whole
// new file, no temporary, and a target that is not a regular file refused.
TEST_F(AtomicFile, RenamedWritesAreWholeAndRefuseWhatSyncedWritesRefuse) {
  using clothlab::io::Durability;
  write_file_atomically(folder_ / "frame.vtp", std::string_view("old"), Durability::Renamed);
  write_file_atomically(
      folder_ / "frame.vtp", [](std::ostream& out) { out << "new frame"; }, Durability::Renamed);
  EXPECT_EQ(read_text(folder_ / "frame.vtp"), "new frame");
  EXPECT_EQ(names(), std::vector<std::string>{"frame.vtp"});
  fs::create_directory(folder_ / "folder.vtp");
  EXPECT_THROW(
      write_file_atomically(folder_ / "folder.vtp", std::string_view("x"), Durability::Renamed),
      WriteError);
}

// The old writers used <name>.tmp-<pid> and .<name>.tmp.<pid> with O_TRUNC: a symlink planted
// there made them overwrite its target.
TEST_F(AtomicFile, APlantedSymlinkAtAPredictableNameIsNotFollowed) {
  const fs::path victim = folder_ / "victim";
  std::ofstream(victim) << "precious";
  const std::string pid = std::to_string(getpid());
  for (const std::string& name : {"out.json.tmp-" + pid, ".out.json.tmp." + pid,
                                  ".out.json.tmp-" + pid, std::string("out.json.tmp")})
    fs::create_symlink(victim, folder_ / name);
  write_file_atomically(folder_ / "out.json", std::string_view("new"));
  EXPECT_EQ(read_text(victim), "precious");
  EXPECT_EQ(read_text(folder_ / "out.json"), "new");
}

TEST_F(AtomicFile, RefusesATargetThatIsNotARegularFile) {
  const fs::path fifo = folder_ / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_EQ(
      message_of([&] { write_file_atomically(fifo, std::string_view("x")); }),
      "cannot write " + fifo.string() + ": it is a FIFO; allowed: a regular file or a new name");
  EXPECT_TRUE(fs::is_fifo(fs::symlink_status(fifo)));

  const fs::path link = folder_ / "link";
  std::ofstream(folder_ / "target") << "kept";
  fs::create_symlink(folder_ / "target", link);
  EXPECT_THROW(write_file_atomically(link, std::string_view("x")), WriteError);
  EXPECT_EQ(read_text(folder_ / "target"), "kept");

  // A private null device (never /dev/null: a broken writer run as root would replace it).
  const fs::path device = folder_ / "null-device";
  if (::mknod(device.c_str(), S_IFCHR | 0666, ::makedev(1, 3)) == 0) {
    EXPECT_THROW(write_file_atomically(device, std::string_view("x")), WriteError);
    EXPECT_TRUE(fs::is_character_file(device));
    EXPECT_THROW(check_output_path(device), WriteError);
  }
  EXPECT_THROW(write_file_atomically(folder_, std::string_view("x")), WriteError);
}

TEST_F(AtomicFile, AReplacedFileKeepsItsMode) {
  const fs::path path = folder_ / "secret.json";
  std::ofstream(path) << "old";
  ASSERT_EQ(::chmod(path.c_str(), 0600), 0);
  write_file_atomically(path, std::string_view("new"));
  struct stat status {};
  ASSERT_EQ(::stat(path.c_str(), &status), 0);
  EXPECT_EQ(status.st_mode & 07777, 0600u);
  EXPECT_EQ(read_text(path), "new");
}

// A writer killed between write and rename left its temporary forever.
TEST_F(AtomicFile, TemporariesOfDeadWritersAreRemovedOnTheNextWrite) {
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ASSERT_GT(dead, 0);
  ::waitpid(dead, nullptr, 0);
  const std::string stale = ".out.csv.tmp-" + std::to_string(dead) + "-123456";
  const std::string live = ".out.csv.tmp-" + std::to_string(getpid()) + "-654321";
  std::ofstream(folder_ / stale) << "partial";
  std::ofstream(folder_ / live) << "in progress";
  write_file_atomically(folder_ / "out.csv", std::string_view("a,b\n"));
  EXPECT_EQ(names(), (std::vector<std::string>{live, "out.csv"}));
  EXPECT_EQ(remove_stale_temporaries(folder_ / "out.csv"), 0);
}

// A writer of many files in one folder (frames) sweeps the folder once, for every name, and
// then writes without scanning it: the dead writer's temporary of a file it writes stays
// until the next sweep, a live writer's and a user's hidden file always stay.
TEST_F(AtomicFile, AFolderIsSweptOnceForTheTemporariesOfDeadWriters) {
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ASSERT_GT(dead, 0);
  ::waitpid(dead, nullptr, 0);
  const std::string stale_frame = ".frame_000001.vtp.tmp-" + std::to_string(dead) + "-1";
  const std::string stale_index = ".frames.pvd.tmp-" + std::to_string(dead) + "-2";
  const std::string live = ".frames.pvd.tmp-" + std::to_string(getpid()) + "-3";
  const std::string hidden = ".notes.tmp-draft";
  for (const std::string& name : {stale_frame, stale_index, live, hidden})
    std::ofstream(folder_ / name) << "x";
  using clothlab::io::Durability;
  using clothlab::io::StaleTemporaries;
  write_file_atomically(folder_ / "frame_000001.vtp", std::string_view("frame"),
                        Durability::Renamed, StaleTemporaries::Skip);
  const auto sorted = [](std::vector<std::string> names) {
    std::sort(names.begin(), names.end());
    return names;
  };
  EXPECT_EQ(names(), sorted({stale_frame, stale_index, live, hidden, "frame_000001.vtp"}));
  EXPECT_EQ(clothlab::io::remove_stale_temporaries_in(folder_), 2);
  EXPECT_EQ(names(), sorted({hidden, live, "frame_000001.vtp"}));
}

TEST_F(AtomicFile, AFailedWriteNamesTheTargetAndLeavesNothing) {
  std::ofstream(folder_ / "out.json") << "old";
  EXPECT_THROW(write_file_atomically(folder_ / "out.json",
                                     [](std::ostream&) { throw std::runtime_error("no data"); }),
               std::runtime_error);
  EXPECT_EQ(read_text(folder_ / "out.json"), "old");
  EXPECT_EQ(names(), std::vector<std::string>{"out.json"});
  const fs::path missing = folder_ / "no-such-folder" / "out.json";
  EXPECT_EQ(message_of([&] { write_file_atomically(missing, std::string_view("x")); }),
            "cannot write " + missing.string() + ": No such file or directory");
}

TEST_F(AtomicFile, OutputPathsAreCheckedBeforeWorkStarts) {
  EXPECT_NO_THROW(check_output_path(folder_ / "new.json"));
  const fs::path missing = folder_ / "no-such-folder" / "out.json";
  EXPECT_EQ(message_of([&] { check_output_path(missing); }),
            "cannot write " + missing.string() + ": folder " + missing.parent_path().string() +
                ": No such file or directory");
  // A file where the folder should be: refused as root too.
  std::ofstream(folder_ / "plain-file") << "x";
  EXPECT_EQ(message_of([&] { check_output_path(folder_ / "plain-file" / "out.json"); }),
            "cannot write " + (folder_ / "plain-file" / "out.json").string() + ": " +
                (folder_ / "plain-file").string() + " is not a folder");
}

// Root writes into any folder, so as root (as CI runs) the check runs in a child that first
// becomes the unprivileged user `nobody` (65534), owner of the read-only folder: the check
// never skips. A child that cannot drop root fails the test.
TEST_F(AtomicFile, AReadOnlyFolderIsRefusedBeforeWorkStarts) {
  constexpr uid_t nobody = 65534;
  clothlab::process::IsolationOptions options;
  options.timeout_s = 30;
  const clothlab::process::ChildOutcome outcome = clothlab::process::run_isolated(
      [&] {
        if (::geteuid() == 0) {
          if (::chown(folder_.c_str(), nobody, nobody) != 0 || ::setgroups(0, nullptr) != 0 ||
              ::setgid(nobody) != 0 || ::setuid(nobody) != 0)
            throw std::runtime_error(std::string("cannot become nobody: ") + std::strerror(errno));
        }
        if (::chmod(folder_.c_str(), 0500) != 0)
          throw std::runtime_error(std::string("chmod: ") + std::strerror(errno));
        return message_of([&] { check_output_path(folder_ / "out.json"); });
      },
      options);
  ::chmod(folder_.c_str(), 0700);
  ASSERT_TRUE(outcome.answered()) << outcome.problem;
  EXPECT_EQ(outcome.answer, "cannot write " + (folder_ / "out.json").string() + ": folder " +
                                folder_.string() + ": Permission denied");
}

}  // namespace
