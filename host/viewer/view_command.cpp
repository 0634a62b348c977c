#include "view_command.hpp"

#include <boost/program_options.hpp>
#include <clothlab/host/errors.hpp>
#include <clothlab/host/subcommand_line.hpp>

#include "view_bundle.hpp"

namespace po = boost::program_options;

namespace clothlab::viewer {

void run_view_command(int argc, const char* const argv[], std::ostream& out) {
  po::options_description options("clothlab view options");
  options.add_options()("help,h", "show this help and exit")(
      "out", po::value<std::string>()->default_value("clothlab-view"),
      "folder for the page (index.html opens from disk)")(
      "max-frames", po::value<size_t>()->default_value(600),
      "thin longer sequences evenly to this many frames")(
      "runs", po::value<std::vector<std::string>>(), "frame folders written by --frames");
  const po::variables_map values = host::parse_subcommand_line(
      argc, argv, options, "runs", "clothlab view: ", "; see view --help");
  if (values.count("help")) {
    out << "Usage: clothlab view RUN_DIR [RUN_DIR...] [--out DIR]\n"
           "Writes a static page that plays the frame folders (clothlab --frames RUN_DIR) side\n"
           "by side or overlaid with one camera: play/pause, scrub, speed, orbit (drag, wheel),\n"
           "colour by stretch, each run's verdict, parameters and energy over time.\n"
           "URL options: index.html?t=SECONDS&paused=1&speed=2&layout=overlay&colour=plain\n\n"
        << options;
    return;
  }
  ViewRequest request;
  if (values.count("runs"))
    for (const std::string& run : values["runs"].as<std::vector<std::string>>())
      request.runs.emplace_back(run);
  if (request.runs.empty())
    throw host::InputError("clothlab view: no frame folder given; usage: clothlab view RUN_DIR...");
  request.out = values["out"].as<std::string>();
  request.max_frames = values["max-frames"].as<size_t>();
  if (request.max_frames < 2)
    throw host::InputError("clothlab view: --max-frames = " + std::to_string(request.max_frames) +
                           ": allowed: 2 or more");
  request.assets = assets_beside_executable();
  const auto index = write_view_bundle(request);
  out << "viewer: file://" << index.string() << "\n"
      << "  a static page: open it in a browser (nothing is served, nothing is downloaded)\n";
}

}  // namespace clothlab::viewer
