// The command line of a subcommand (clothlab merge, clothlab view, clothlab-conformance): its
// options, and its positional arguments under one option name. Header-only, for the programs
// that already link Boost.Program_options.
#pragma once

#include <boost/program_options.hpp>
#include <clothlab/host/errors.hpp>
#include <string>

namespace clothlab::host {

// Throws InputError "PREFIX<Boost's reason>SUFFIX" for a command line that does not parse.
inline boost::program_options::variables_map parse_subcommand_line(
    int argc, const char* const argv[], const boost::program_options::options_description& options,
    const char* positional_name, const std::string& prefix, const std::string& suffix) {
  namespace po = boost::program_options;
  po::positional_options_description positional;
  positional.add(positional_name, -1);
  po::variables_map values;
  try {
    po::store(po::command_line_parser(argc, argv).options(options).positional(positional).run(),
              values);
    po::notify(values);
  } catch (const po::error& error) {
    throw InputError(prefix + error.what() + suffix);
  }
  return values;
}

}  // namespace clothlab::host
