#include <gtest/gtest.h>
#include <stdlib.h>

#include <clothlab/host/errors.hpp>
#include <clothlab/host/plugin_search_path.hpp>
#include <fstream>

#include "test_paths.hpp"

namespace clothlab::host {
namespace {

namespace fs = std::filesystem;
using test::test_plugin_dir;

TEST(SplitPathList, DropsEmptyEntries) {
  EXPECT_EQ(split_path_list("a:b::c:"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_TRUE(split_path_list("").empty());
}

TEST(PluginSearchPath, CommandLineThenEnvironmentThenBesideTheExecutable) {
  setenv("CLOTHLAB_PLUGIN_PATH", "/env/one:/env/two", 1);
  const PluginSearchPath path = PluginSearchPath::standard({"/cli/a:/cli/b", "/cli/c"});
  unsetenv("CLOTHLAB_PLUGIN_PATH");
  const auto& dirs = path.directories();
  ASSERT_GE(dirs.size(), 6u);
  const std::vector<fs::path> first(dirs.begin(), dirs.begin() + 5);
  EXPECT_EQ(first, (std::vector<fs::path>{"/cli/a", "/cli/b", "/cli/c", "/env/one", "/env/two"}));
  const fs::path beside = dirs[5];
  EXPECT_EQ(beside.filename(), "plugins");
  EXPECT_EQ(beside.parent_path().filename(), "clothlab");
}

TEST(PluginSearchPath, ResolvesNameAndNameWithSuffixToTheSameFile) {
  const PluginSearchPath path({"/nonexistent", test_plugin_dir("good")});
  const fs::path expected = test_plugin_dir("good") / "clothlab_test_good.so";
  EXPECT_EQ(path.resolve("clothlab_test_good"), expected);
  EXPECT_EQ(path.resolve("clothlab_test_good.so"), expected);
}

TEST(PluginSearchPath, AnArgumentWithASlashIsAPath) {
  const PluginSearchPath nowhere(std::vector<fs::path>{});
  const fs::path expected = test_plugin_dir("good") / "clothlab_test_good.so";
  EXPECT_EQ(nowhere.resolve(expected.string()), expected);
}

TEST(PluginSearchPath, MissingPluginListsEveryFolderSearched) {
  const PluginSearchPath path({"/first/folder", "/second/folder"});
  try {
    path.resolve("nothing");
    FAIL() << "resolved a plugin that does not exist";
  } catch (const PluginLoadError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("nothing.so"), std::string::npos) << message;
    EXPECT_NE(message.find("/first/folder:/second/folder"), std::string::npos) << message;
  }
}

TEST(PluginSearchPath, EarlierFoldersHideLibrariesOfTheSameName) {
  const fs::path root = fs::temp_directory_path() / ("clothlab_search_" + std::to_string(getpid()));
  fs::create_directories(root / "one");
  fs::create_directories(root / "two");
  for (const char* file : {"one/p.so", "two/p.so", "two/q.so", "two/notes.txt"})
    std::ofstream(root / file) << "x";
  const auto libraries = PluginSearchPath({root / "one", root / "two"}).libraries();
  fs::remove_all(root);
  EXPECT_EQ(libraries, (std::vector<fs::path>{root / "one/p.so", root / "two/q.so"}));
}

}  // namespace
}  // namespace clothlab::host
