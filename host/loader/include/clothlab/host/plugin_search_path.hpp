// Where plugin libraries are looked for, and how a plugin argument becomes a file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace clothlab::host {

class PluginSearchPath {
 public:
  explicit PluginSearchPath(std::vector<std::filesystem::path> directories);

  // --plugin-path entries (each may hold ':'-separated folders), then the folders in
  // CLOTHLAB_PLUGIN_PATH, then the plugin folder beside the running executable.
  static PluginSearchPath standard(const std::vector<std::string>& command_line_entries);
  // The same with other installed plugin folders last (the Python module's, found from the
  // module's own location rather than the interpreter's).
  static PluginSearchPath standard(const std::vector<std::string>& command_line_entries,
                                   std::vector<std::filesystem::path> installed_folders);

  // The plugin folder relative to the running executable (bin/../lib/clothlab/plugins).
  static std::vector<std::filesystem::path> beside_executable();

  const std::vector<std::filesystem::path>& directories() const { return directories_; }
  // "dir1:dir2:..." for error messages.
  std::string describe() const;

  // An argument containing '/' is a path (relative to the working directory); otherwise
  // NAME or NAME.so is looked up as NAME.so in each folder in order. Throws
  // PluginLoadError naming the argument and every place searched.
  std::filesystem::path resolve(std::string_view argument) const;

  // Every *.so in the folders, sorted by name per folder; a file name found in an earlier
  // folder hides the same name in later ones (as PATH does).
  std::vector<std::filesystem::path> libraries() const;

 private:
  std::vector<std::filesystem::path> directories_;
};

// Splits "a:b::c" into {"a", "b", "c"} (empty entries dropped).
std::vector<std::string> split_path_list(std::string_view list);

}  // namespace clothlab::host
