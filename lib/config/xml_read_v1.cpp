// Reading format version 1 XML files (config/migrate.hpp migrates them).
// The layout is frozen: it is not described by the field tables.
#include "config/io_common.hpp"
#include "config/xml_fields.hpp"

namespace lmcfg::config::detail {

Result<ConfigV1> read_xml_v1(const XmlReader& r, xml_node root) {
  LMCFG_TRY(r.shape(root, {"format", "format_version"},
                    {"drive", "parameters", "curves", "command_table"}));
  ConfigV1 v1;
  v1.field_sep = "/@";
  LMCFG_ASSIGN_OR_RETURN(xml_node drive, r.single(root, "drive", false));
  if (drive) {
    LMCFG_TRY(r.shape(
        drive,
        {"macid", "port", "baud", "parity", "stop_bits", "checksum", "tool_version", "captured_at"},
        {}));
    LMCFG_ASSIGN_OR_RETURN(v1.macid, r.attr(drive, "macid", false));
    LMCFG_ASSIGN_OR_RETURN(v1.port, r.attr(drive, "port", false));
    LMCFG_ASSIGN_OR_RETURN(v1.parity, r.attr(drive, "parity", false));
    LMCFG_ASSIGN_OR_RETURN(v1.stop_bits, r.attr(drive, "stop_bits", false));
    LMCFG_ASSIGN_OR_RETURN(v1.checksum, r.attr(drive, "checksum", false));
    LMCFG_ASSIGN_OR_RETURN(v1.tool_version, r.attr(drive, "tool_version", false));
    LMCFG_ASSIGN_OR_RETURN(v1.captured_at, r.attr(drive, "captured_at", false));
    if (drive.attribute("baud")) {
      LMCFG_ASSIGN_OR_RETURN(auto baud, r.uint_attr(drive, "baud", 0xFFFFFFFFu, "a baud rate"));
      v1.baud = std::to_string(baud);
    }
  }
  LMCFG_ASSIGN_OR_RETURN(xml_node params, r.single(root, "parameters", true));
  LMCFG_TRY(r.shape(params, {}, {"param"}));
  for (xml_node pn : params.children("param")) {
    LMCFG_TRY(r.shape(pn, {"upid", "value"}, {}));
    ConfigV1::Param p;
    LMCFG_ASSIGN_OR_RETURN(p.upid, r.int_attr(pn, "upid", "a decimal UPID"));
    LMCFG_ASSIGN_OR_RETURN(p.value, r.int_attr(pn, "value", "a decimal value"));
    p.where = r.where(pn);
    v1.params.push_back(std::move(p));
  }
  auto blocks = [&](const char* list, const char* item, bool curve,
                    std::vector<ConfigV1::Block>& out) -> Result<void> {
    LMCFG_ASSIGN_OR_RETURN(xml_node ln, r.single(root, list, false));
    if (!ln) return {};
    LMCFG_TRY(r.shape(ln, {}, {item}));
    for (xml_node n : ln.children(item)) {
      if (curve) {
        LMCFG_TRY(r.shape(n, {"id", "info", "data"}, {}));
      } else {
        LMCFG_TRY(r.shape(n, {"id", "data"}, {}));
      }
      ConfigV1::Block b;
      LMCFG_ASSIGN_OR_RETURN(b.id, r.int_attr(n, "id", "a decimal ID"));
      for (const char* field : {"info", "data"}) {
        if (!curve && std::string_view(field) == "info") continue;
        LMCFG_ASSIGN_OR_RETURN(auto hs, r.attr(n, field, true));
        auto bytes = from_hex(hs);
        if (!bytes)
          return r.err_attr(Errc::parse_error, n, field, "expected hex bytes (\"46 00 03 00\")");
        (std::string_view(field) == "info" ? b.info : b.data) = std::move(*bytes);
      }
      b.where = r.where(n);
      out.push_back(std::move(b));
    }
    return {};
  };
  LMCFG_TRY(blocks("curves", "curve", true, v1.curves));
  LMCFG_TRY(blocks("command_table", "entry", false, v1.ct_entries));
  return v1;
}

}  // namespace lmcfg::config::detail
