// Reading format version 1 JSON files (config/migrate.hpp migrates them).
// The layout is frozen: it is not described by the field tables.
#include "config/io_common.hpp"
#include "config/json_fields.hpp"

namespace lmcfg::config::detail {

Result<ConfigV1> read_json_v1(const JsonReader& r, const json& doc) {
  const Ptr root;
  LMCFG_TRY(r.keys(doc, root,
                   {"format", "format_version", "drive", "parameters", "curves", "command_table"}));
  ConfigV1 v1;
  v1.field_sep = "/";
  LMCFG_ASSIGN_OR_RETURN(const json* dj, r.member(doc, root, "drive", false));
  if (dj) {
    const Ptr p = root / "drive";
    LMCFG_TRY(r.object(*dj, p));
    LMCFG_TRY(r.keys(*dj, p,
                     {"macid", "port", "baud", "parity", "stop_bits", "checksum", "tool_version",
                      "captured_at"}));
    LMCFG_TRY(r.opt_string(*dj, p, "macid", v1.macid));
    LMCFG_TRY(r.opt_string(*dj, p, "port", v1.port));
    LMCFG_TRY(r.opt_string(*dj, p, "parity", v1.parity));
    LMCFG_TRY(r.opt_string(*dj, p, "stop_bits", v1.stop_bits));
    LMCFG_TRY(r.opt_string(*dj, p, "checksum", v1.checksum));
    LMCFG_TRY(r.opt_string(*dj, p, "tool_version", v1.tool_version));
    LMCFG_TRY(r.opt_string(*dj, p, "captured_at", v1.captured_at));
    LMCFG_ASSIGN_OR_RETURN(const json* bj, r.member(*dj, p, "baud", false));
    if (bj) {
      LMCFG_ASSIGN_OR_RETURN(auto baud,
                             r.unsigned_int(*bj, p / "baud", 0xFFFFFFFFu, "a baud rate"));
      v1.baud = std::to_string(baud);
    }
  }
  LMCFG_ASSIGN_OR_RETURN(const json* pj, r.member(doc, root, "parameters", true));
  LMCFG_TRY(r.array(*pj, root / "parameters"));
  for (std::size_t i = 0; i < pj->size(); ++i) {
    const Ptr pp = root / "parameters" / i;
    const json& q = (*pj)[i];
    LMCFG_TRY(r.object(q, pp));
    LMCFG_TRY(r.keys(q, pp, {"upid", "value"}));
    ConfigV1::Param prm;
    LMCFG_ASSIGN_OR_RETURN(const json* uj, r.member(q, pp, "upid", true));
    LMCFG_ASSIGN_OR_RETURN(prm.upid, r.signed_int(*uj, pp / "upid", "a decimal UPID"));
    LMCFG_ASSIGN_OR_RETURN(const json* vj, r.member(q, pp, "value", true));
    LMCFG_ASSIGN_OR_RETURN(prm.value, r.signed_int(*vj, pp / "value", "a decimal value"));
    prm.where = r.loc(pp);
    v1.params.push_back(std::move(prm));
  }
  auto blocks = [&](std::string_view key, bool curve,
                    std::vector<ConfigV1::Block>& out) -> Result<void> {
    LMCFG_ASSIGN_OR_RETURN(const json* aj, r.member(doc, root, key, false));
    if (!aj) return {};
    const Ptr p = root / key;
    LMCFG_TRY(r.array(*aj, p));
    for (std::size_t i = 0; i < aj->size(); ++i) {
      const Ptr bp = p / i;
      const json& b = (*aj)[i];
      LMCFG_TRY(r.object(b, bp));
      if (curve) {
        LMCFG_TRY(r.keys(b, bp, {"id", "info", "data"}));
      } else {
        LMCFG_TRY(r.keys(b, bp, {"id", "data"}));
      }
      ConfigV1::Block blk;
      LMCFG_ASSIGN_OR_RETURN(const json* ij, r.member(b, bp, "id", true));
      LMCFG_ASSIGN_OR_RETURN(blk.id, r.signed_int(*ij, bp / "id", "a decimal ID"));
      for (std::string_view field : {std::string_view("info"), std::string_view("data")}) {
        if (field == "info" && !curve) continue;
        LMCFG_ASSIGN_OR_RETURN(const json* hj, r.member(b, bp, field, true));
        LMCFG_ASSIGN_OR_RETURN(auto hs, r.string(*hj, bp / field));
        auto bytes = from_hex(hs);
        if (!bytes)
          return r.err(Errc::parse_error, bp / field, "expected hex bytes (\"46 00 03 00\")");
        (field == "info" ? blk.info : blk.data) = std::move(*bytes);
      }
      blk.where = r.loc(bp);
      out.push_back(std::move(blk));
    }
    return {};
  };
  LMCFG_TRY(blocks("curves", true, v1.curves));
  LMCFG_TRY(blocks("command_table", false, v1.ct_entries));
  return v1;
}

}  // namespace lmcfg::config::detail
