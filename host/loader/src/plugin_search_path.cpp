#include "clothlab/host/plugin_search_path.hpp"

#include <algorithm>
#include <cstdlib>
#include <set>
#include <system_error>

#include "clothlab/host/errors.hpp"

namespace fs = std::filesystem;

namespace clothlab::host {

namespace {

constexpr std::string_view library_suffix = ".so";

bool ends_with_suffix(std::string_view text) {
  return text.size() > library_suffix.size() && text.ends_with(library_suffix);
}

}  // namespace

std::vector<std::string> split_path_list(std::string_view list) {
  std::vector<std::string> parts;
  while (!list.empty()) {
    const size_t colon = list.find(':');
    const std::string_view part = list.substr(0, colon);
    if (!part.empty()) parts.emplace_back(part);
    if (colon == std::string_view::npos) break;
    list.remove_prefix(colon + 1);
  }
  return parts;
}

PluginSearchPath::PluginSearchPath(std::vector<fs::path> directories)
    : directories_(std::move(directories)) {}

std::vector<fs::path> PluginSearchPath::beside_executable() {
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  if (error) return {};
  const fs::path bin = executable.parent_path();
  std::vector<fs::path> folders{(bin / CLOTHLAB_PLUGINS_FROM_BIN).lexically_normal()};
  // The build tree always uses lib/clothlab/plugins, whatever the install libdir is.
  const fs::path build_tree = (bin / "../lib/clothlab/plugins").lexically_normal();
  if (build_tree != folders.front()) folders.push_back(build_tree);
  return folders;
}

PluginSearchPath PluginSearchPath::standard(const std::vector<std::string>& command_line_entries) {
  return standard(command_line_entries, beside_executable());
}

PluginSearchPath PluginSearchPath::standard(const std::vector<std::string>& command_line_entries,
                                            std::vector<fs::path> installed_folders) {
  std::vector<fs::path> directories;
  for (const std::string& entry : command_line_entries)
    for (const std::string& folder : split_path_list(entry)) directories.emplace_back(folder);
  if (const char* environment = std::getenv("CLOTHLAB_PLUGIN_PATH"))
    for (const std::string& folder : split_path_list(environment)) directories.emplace_back(folder);
  for (fs::path& folder : installed_folders) directories.push_back(std::move(folder));
  return PluginSearchPath(std::move(directories));
}

std::string PluginSearchPath::describe() const {
  std::string text;
  for (const fs::path& folder : directories_) {
    if (!text.empty()) text += ':';
    text += folder.string();
  }
  return text.empty() ? "(no folders)" : text;
}

fs::path PluginSearchPath::resolve(std::string_view argument) const {
  if (argument.empty()) throw PluginLoadError("empty plugin name");
  if (argument.find('/') != std::string_view::npos) {
    const fs::path path = fs::absolute(fs::path(argument)).lexically_normal();
    // Asked without exceptions: a name too long for the file system is an answer, not a crash.
    std::error_code error;
    const fs::file_status status = fs::status(path, error);
    if (!fs::exists(status))
      throw PluginLoadError("plugin file " + path.string() + " does not exist" +
                            (error && error != std::errc::no_such_file_or_directory
                                 ? " (" + error.message() + ")"
                                 : ""));
    if (!fs::is_regular_file(status))
      throw PluginLoadError("plugin file " + path.string() + " is " +
                            (fs::is_directory(status) ? "a folder" : "a device or special file") +
                            ", not a shared library");
    return path;
  }
  std::string file_name(argument);
  if (!ends_with_suffix(file_name)) file_name += library_suffix;
  for (const fs::path& folder : directories_) {
    const fs::path candidate = folder / file_name;
    std::error_code error;
    if (fs::is_regular_file(candidate, error)) return fs::absolute(candidate).lexically_normal();
  }
  throw PluginLoadError("plugin " + std::string(argument) + ": no " + file_name +
                        " in the plugin search path " + describe());
}

std::vector<fs::path> PluginSearchPath::libraries() const {
  std::vector<fs::path> found;
  std::set<fs::path> seen_names;
  for (const fs::path& folder : directories_) {
    std::error_code error;
    std::vector<fs::path> in_folder;
    for (fs::directory_iterator it(folder, error), end; !error && it != end; it.increment(error)) {
      const fs::path& path = it->path();
      if (ends_with_suffix(path.filename().string()) && it->is_regular_file(error))
        in_folder.push_back(path);
    }
    std::sort(in_folder.begin(), in_folder.end());
    for (fs::path& path : in_folder)
      if (seen_names.insert(path.filename()).second)
        found.push_back(fs::absolute(path).lexically_normal());
  }
  return found;
}

}  // namespace clothlab::host
