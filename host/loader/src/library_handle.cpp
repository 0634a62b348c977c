#include "clothlab/host/library_handle.hpp"

#include <dlfcn.h>

#include <string>

#include "clothlab/host/errors.hpp"

namespace fs = std::filesystem;

namespace clothlab::host {

namespace {

// A bare file name would send dlopen searching the library path; the file meant is the one here.
fs::path as_dlopen_path(const fs::path& path) {
  return path.has_parent_path() ? path : fs::path(".") / path;
}

// dlerror()'s reason, without the path it starts with (the caller's message names the file).
std::string dlopen_reason(const fs::path& opened) {
  const char* reason = dlerror();
  std::string text = reason != nullptr ? reason : "unknown dlopen failure";
  const std::string prefix = opened.string() + ": ";
  if (text.starts_with(prefix)) text.erase(0, prefix.size());
  return text;
}

}  // namespace

std::shared_ptr<const LibraryHandle> LibraryHandle::open(const fs::path& path,
                                                         std::string_view searched) {
  std::error_code exists_error;
  if (!fs::exists(path, exists_error)) throw cannot_load(path, "no such file", searched);
  const fs::path opened = as_dlopen_path(path);
  void* library = dlopen(opened.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (library == nullptr)
    throw cannot_load(path, "not a loadable shared library: " + dlopen_reason(opened), searched);
  auto entry =
      reinterpret_cast<clothlab_plugin_entry_fn>(dlsym(library, CLOTHLAB_PLUGIN_ENTRY_SYMBOL));
  if (entry == nullptr) {
    dlclose(library);
    throw cannot_load(
        path, "no entry symbol " CLOTHLAB_PLUGIN_ENTRY_SYMBOL " (not a ClothLab plugin)", searched);
  }
  return std::shared_ptr<const LibraryHandle>(new LibraryHandle(library, entry));
}

LibraryHandle::~LibraryHandle() { dlclose(library_); }

bool LibraryHandle::is_loaded(const fs::path& path) {
  const fs::path opened = as_dlopen_path(path);
  void* library = dlopen(opened.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NOLOAD);
  if (library == nullptr) return false;
  dlclose(library);  // RTLD_NOLOAD still took a reference
  return true;
}

}  // namespace clothlab::host
