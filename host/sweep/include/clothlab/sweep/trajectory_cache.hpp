// A folder of finished trajectories, so that an expensive run is computed once: `clothlab
// --choose`'s float64 reference serves every later search of the same problem (other scene
// meshes with the same error mesh, other frame rates with the same reference step, reruns).
// A run is identified by its effective settings (the last value of each key; the timeout,
// which cannot change a finished run, left out: the material's numbers, the mesh, the
// precision...), the content of every file a setting names (a mesh file edited in place), the
// identity of its plugin files and that of the host (its forces and stepping are the host's
// code), so a changed scene or a rebuilt plugin or host is never served a stale result. One JSON
// file per run, named by the hash of that identity and holding it in full (a hash collision is a
// miss, not a wrong answer).
#pragma once

#include <filesystem>
#include <string>

#include "clothlab/sweep/case_spec.hpp"
#include "clothlab/sweep/fingerprint.hpp"
#include "clothlab/sweep/work_precision.hpp"

namespace clothlab::sweep {

class TrajectoryCache {
 public:
  // The folder is created when the first run is stored. plugin_identity: as for fingerprints;
  // host_identity: the running host's (e.g. its executable's size and hash).
  TrajectoryCache(std::filesystem::path folder, PluginIdentity plugin_identity,
                  std::string host_identity);

  // The stored result of an identical earlier case, or runner(c) (stored when stable).
  // Throws SweepError when a result cannot be stored.
  Trajectory run(const TrajectoryRunner& runner, const CaseSpec& c);

  // The runs served from the folder so far, and the file a case is stored in.
  int hits() const { return hits_; }
  std::filesystem::path path_of(const CaseSpec& c) const;

 private:
  std::string identity(const CaseSpec& c) const;

  std::filesystem::path folder_;
  PluginIdentity plugin_identity_;
  std::string host_identity_;
  int hits_ = 0;
};

}  // namespace clothlab::sweep
