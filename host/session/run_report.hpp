// What a run reports: its summary (as JSON and in words), the energy trace and the final state
// as CSV.
#pragma once

#include <clothlab/core/cloth.hpp>
#include <clothlab/host/run_summary.hpp>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>

#include "simulation.hpp"

namespace clothlab::cli {

// The figures of a run record: its times' medians and percentiles, rates and stretch.
host::RunSummary summarize(const RunRecord& record);
// to_json of its summary: the run JSON.
nlohmann::json summary_json(const RunRecord& record);
std::string human_summary(const host::RunSummary& run);
// Header integrator,t,kinetic,spring,gravity,total (J); 17 significant digits.
void write_energy_csv(const RunRecord& record, std::ostream& out);
// Header row,col,x,y,z,vx,vy,vz; values with 17 significant digits.
void write_state_csv(const Cloth& cloth, std::ostream& out);

}  // namespace clothlab::cli
