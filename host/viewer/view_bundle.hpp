// `clothlab view`: a static page (a folder that opens from disk, no server, nothing from the
// internet) that plays frame folders written by --frames. The page, its script and three.js
// are copied from the viewer assets; the runs are embedded as runs.js, because browsers
// refuse fetch() on file:// pages.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace clothlab::viewer {

struct ViewRequest {
  std::vector<std::filesystem::path> runs;  // frame folders (each with frames.pvd, run.json)
  std::filesystem::path out;                // the bundle folder
  std::filesystem::path assets;             // index.html, viewer.js, viewer.css, three.min.js
  size_t max_frames = 600;                  // more frames are thinned evenly to this many
};

// The viewer assets installed beside the running program (bin/../share/clothlab/viewer).
std::filesystem::path assets_beside_executable();

// Writes the bundle and returns the path of its index.html. Throws host::InputError (one
// line) for a folder without frames, an unreadable frame or an unwritable output folder.
std::filesystem::path write_view_bundle(const ViewRequest& request);

}  // namespace clothlab::viewer
