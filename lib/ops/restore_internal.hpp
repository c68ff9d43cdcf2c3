#pragma once
// Helpers shared by the restore phases (restore_*.cpp); not a public API.
#include <cstdint>
#include <optional>
#include <string>

#include "config/model.hpp"
#include "db/database.hpp"

namespace lmcfg::ops::detail {

// "MC 13A2h P Gain" (name from the database, else from the file's record).
std::string param_label(int layer, std::uint16_t upid, const db::Parameter* d,
                        const config::Parameter* p);
std::string param_name(std::uint16_t upid, const db::Parameter* d, const config::Parameter* p);
// A curve's name from its info block (offset 8, up to 22 characters, §11 /
// docs/config-files.md); "" when the block is too short.
std::string curve_name(const Bytes& info);

}  // namespace lmcfg::ops::detail
