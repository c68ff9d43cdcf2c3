#include "config/migrate.hpp"

#include <map>
#include <utility>

#include "common/layers.hpp"
#include "config/io_common.hpp"

namespace lmcfg::config {

Result<DriveConfig> migrate_v1_to_v2(const ConfigV1& v1) {
  DriveConfig cfg;
  auto& id = cfg.identity;
  id.macid = v1.macid;
  id.link = LinkSettings{v1.port, v1.baud, v1.parity, v1.stop_bits, v1.checksum};
  id.tool_version = v1.tool_version;
  id.captured_at = v1.captured_at;
  // v1 always captured the modified parameters of all four layers, every curve
  // and the command table.
  cfg.scope = Scope{};

  // Parameters: layer from the UPID range, value to the raw 32-bit field.
  std::map<std::uint32_t, const ConfigV1::Param*> seen;
  for (const auto& p : v1.params) {
    if (p.upid < 0 || p.upid > 0xFFFF)
      return Error(Errc::validation_failed, p.where + v1.field_sep +
                                                "upid: expected a UPID 0..65535, found " +
                                                std::to_string(p.upid));
    const auto upid = static_cast<std::uint32_t>(p.upid);
    const int layer = lmcfg::layers::of_upid(upid);
    if (layer == 0)
      return Error(Errc::validation_failed,
                   p.where + v1.field_sep + "upid: UPID " + std::to_string(p.upid) + " (" +
                       detail::upid_hex(upid) +
                       "h) is in no layer's range (0000-0EFF, 1000-1EFF, 2000-2EFF, 3000-3EFF)");
    if (auto [it, inserted] = seen.emplace(upid, &p); !inserted)
      return Error(Errc::validation_failed, p.where + v1.field_sep + "upid: duplicate UPID " +
                                                std::to_string(p.upid) + " (" +
                                                detail::upid_hex(upid) + "h)");
    if (p.value < -2147483648LL || p.value > 4294967295LL)
      return Error(Errc::validation_failed,
                   p.where + v1.field_sep +
                       "value: expected a 32-bit value (-2147483648..4294967295), found " +
                       std::to_string(p.value));
    Parameter np;
    np.upid = static_cast<std::uint16_t>(upid);
    np.value = static_cast<std::uint32_t>(static_cast<std::uint64_t>(p.value) & 0xFFFFFFFFu);
    cfg.layer(layer).push_back(std::move(np));
  }

  for (const auto& c : v1.curves) {
    if (c.id < 0 || c.id > 0xFFFF)
      return Error(Errc::validation_failed, c.where + v1.field_sep +
                                                "id: expected a curve ID 0..65535, found " +
                                                std::to_string(c.id));
    cfg.curves.push_back(Curve{static_cast<std::uint32_t>(c.id), c.info, c.data});
  }
  for (const auto& e : v1.ct_entries) {
    if (e.id < 0 || e.id > kMaxCtEntryId)
      return Error(Errc::validation_failed, e.where + v1.field_sep + "id: command table entry ID " +
                                                std::to_string(e.id) + " is outside 0..255");
    cfg.ct_entries.push_back(CtEntry{static_cast<std::uint32_t>(e.id), e.data});
  }

  if (auto is = find_issue(cfg)) {
    // Parameters were checked above; what is left refers to curves and entries,
    // whose order is the v1 file's.
    std::string where = "migration";
    if (is->where == Issue::Where::curve && is->index < v1.curves.size())
      where = v1.curves[is->index].where + v1.field_sep + is->field;
    else if (is->where == Issue::Where::ct_entry && is->index < v1.ct_entries.size())
      where =
          v1.ct_entries[is->index].where + v1.field_sep + (is->field == "raw" ? "data" : is->field);
    else if (is->where == Issue::Where::identity)
      where = "identity " + is->field;
    return Error(Errc::validation_failed, where + ": " + is->message);
  }
  canonicalize(cfg);
  return cfg;
}

}  // namespace lmcfg::config
