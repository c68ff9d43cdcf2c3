// Restore: what the phases share. The phases live in restore_plan.cpp,
// restore_execute.cpp, restore_verify.cpp and restore_render.cpp.
#include "ops/restore.hpp"

#include <cstdio>

#include "common/bytes.hpp"
#include "db/database.hpp"
#include "ops/restore_internal.hpp"

namespace lmcfg::ops {

bool is_comm_parameter(const db::Database* db, std::uint16_t upid) {
  if (upid == kBaudRateSource || upid == kBaudRateCode || upid == kMacidSource ||
      upid == kMacidValue)
    return true;
  const db::Parameter* d = db ? db->find(upid) : nullptr;
  return d && d->comm;
}

namespace detail {

std::string param_name(std::uint16_t, const db::Parameter* d, const config::Parameter* p) {
  return d && !d->name.empty() ? d->name : (p ? p->name : std::string());
}

std::string param_label(int layer, std::uint16_t upid, const db::Parameter* d,
                        const config::Parameter* p) {
  std::string s = std::string(config::layer_name(layer)) + " " + hex(upid, 4, "h");
  const std::string name = param_name(upid, d, p);
  if (!name.empty()) s += " " + name;
  return s;
}

std::optional<std::int64_t> as_integer(db::TypeCode t, std::uint32_t raw) {
  const unsigned bits = 8 * db::type_size(t);
  if (db::is_text_type(t) || t == db::TypeCode::LinFloat) return static_cast<std::int64_t>(raw);
  if (t == db::TypeCode::Bool || t == db::TypeCode::RadioDirBit)
    return raw <= 1 ? std::optional<std::int64_t>(raw) : std::nullopt;
  if (bits >= 32) {
    return db::is_signed_type(t) ? static_cast<std::int64_t>(static_cast<std::int32_t>(raw))
                                 : static_cast<std::int64_t>(raw);
  }
  const std::uint32_t mask = (1u << bits) - 1;
  const std::uint32_t upper = raw & ~mask;
  if (upper == 0) {
    if (!db::is_signed_type(t)) return static_cast<std::int64_t>(raw);
    const std::uint32_t sign = 1u << (bits - 1);
    return (raw & sign) ? static_cast<std::int64_t>(raw) - (static_cast<std::int64_t>(1) << bits)
                        : static_cast<std::int64_t>(raw);
  }
  if (db::is_signed_type(t) && upper == ~mask && (raw & (1u << (bits - 1)))) {
    return static_cast<std::int64_t>(static_cast<std::int32_t>(raw));
  }
  return std::nullopt;
}

std::string curve_name(const Bytes& info) {
  std::string name;
  for (std::size_t i = 8; i < 30 && i < info.size() && info[i] != 0; ++i)
    name.push_back(static_cast<char>(info[i]));
  return name;
}

}  // namespace detail
}  // namespace lmcfg::ops
