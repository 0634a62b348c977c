// What a run reports: the JSON summary, the human summary and the final state as CSV.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "simulation.hpp"

namespace clothlab::cli {

// Derived figures of a run record.
struct RunFigures {
  double sim_time_s = 0;   // steps taken * dt
  double wall_time_s = 0;  // time spent inside the integrator's step calls
  double ms_median = 0, ms_p10 = 0, ms_p90 = 0;
  double internal_ms = 0, external_ms = 0, integrate_ms = 0;       // medians per step
  double frame_ms_median = 0, frame_ms_p10 = 0, frame_ms_p90 = 0;  // substeps per frame summed
  double frames_per_second = 0;  // achievable: 1000 / frame_ms_median
  double springs_per_second = 0;
  double real_time_factor = 0;
};
RunFigures compute_figures(const RunRecord& record);

nlohmann::json summary_json(const RunRecord& record);
std::string human_summary(const RunRecord& record);
// Header integrator,t,kinetic,spring,gravity,total (J); 17 significant digits.
void write_energy_csv(const RunRecord& record, std::ostream& out);
// Header row,col,x,y,z,vx,vy,vz; values with 17 significant digits.
void write_state_csv(const Cloth& cloth, std::ostream& out);

}  // namespace clothlab::cli
