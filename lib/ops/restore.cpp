// Restore: what the phases share. The phases live in restore_plan.cpp (with
// restore_check.cpp and restore_tables.cpp), restore_execute.cpp,
// restore_verify.cpp and restore_render.cpp; they compare through
// ops/compare.hpp.
#include "ops/restore.hpp"

#include <cstdio>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "db/database.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops {

bool is_comm_parameter(const db::Database& db, std::uint16_t upid) {
  if (upid == kBaudRateSource || upid == kBaudRateCode || upid == kMacidSource ||
      upid == kMacidValue)
    return true;
  const db::Parameter* d = db.find(upid);
  return d && d->comm;
}

namespace detail {

std::string param_name(std::uint16_t, const db::Parameter* d, const config::Parameter* p) {
  return d && !d->name.empty() ? d->name : (p ? p->name : std::string());
}

std::string param_label(int layer, std::uint16_t upid, const db::Parameter* d,
                        const config::Parameter* p) {
  std::string s = std::string(lmcfg::layers::name(layer)) + " " + hex(upid, 4, "h");
  const std::string name = param_name(upid, d, p);
  if (!name.empty()) s += " " + name;
  return s;
}

std::string curve_name(const Bytes& info) {
  std::string name;
  for (std::size_t i = 8; i < 30 && i < info.size() && info[i] != 0; ++i)
    name.push_back(static_cast<char>(info[i]));
  return name;
}

}  // namespace detail
}  // namespace lmcfg::ops
