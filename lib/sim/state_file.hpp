#pragma once
// The "sim state file": a Drive's state as JSON (format in docs/simulator.md,
// fixtures in tests/fixtures/sim/). Format id "lmcfg-sim-state", version 1.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "common/result.hpp"
#include "sim/drive.hpp"
#include "transport/transport.hpp"

namespace lmcfg::sim {

inline constexpr const char* kStateFormat = "lmcfg-sim-state";
inline constexpr int kStateVersion = 1;

nlohmann::json to_json(const DriveState& s);
// Errors: parse_error (bad JSON / wrong field types), unsupported_version.
Result<DriveState> from_json(const nlohmann::json& j);

Result<DriveState> load_state(const std::string& path);
// The states of the drives on one RS485 line, in the order given; two with
// the same MACID are refused (Errc::invalid_argument naming both files).
Result<std::vector<DriveState>> load_line(const std::vector<std::string>& paths);
// Written to `path`.tmp, then renamed over `path`.
Result<void> save_state(const DriveState& s, const std::string& path);

// The factory of "sim:STATE.json" ports, which the tools register with
// link::register_scheme("sim", ...): loads the drive from STATE.json, wires
// the line at the drive's settings and saves the state back on a clean close.
transport::LinkFactory state_file_link_factory();

}  // namespace lmcfg::sim
