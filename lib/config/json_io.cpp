#include "config/json_io.hpp"

#include <utility>

#include "common/layers.hpp"
#include "config/atomic_file.hpp"
#include "config/io_common.hpp"
#include "config/json_fields.hpp"
#include "config/migrate.hpp"

namespace lmcfg::config {

using json = nlohmann::json;
using detail::JsonReader;
using detail::Ptr;

TextPos text_position(std::string_view text, std::size_t offset) noexcept {
  TextPos p;
  if (offset > text.size()) offset = text.size();
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++p.line;
      p.column = 1;
    } else {
      ++p.column;
    }
  }
  return p;
}

namespace {

// Index of each layer (1..4) in the document's "parameters" array.
using LayerIndex = std::array<std::size_t, lmcfg::layers::kCount>;

// Where a validation issue of the model is in the document.
Ptr issue_pointer(const Issue& is, const LayerIndex& layer_index) {
  Ptr p;
  switch (is.where) {
    case Issue::Where::identity:
      p = p / "identity";
      if (is.field.rfind("labels.", 0) == 0) {
        p = p / "labels" / std::string_view(is.field).substr(7);
      } else if (auto dot = is.field.find('.'); dot != std::string::npos) {
        p = p / std::string_view(is.field).substr(0, dot) /
            std::string_view(is.field).substr(dot + 1);
      } else {
        p = p / is.field;
      }
      break;
    case Issue::Where::scope:
      p = p / "scope" / is.field;
      break;
    case Issue::Where::layer:
      p = p / "parameters" / layer_index[static_cast<std::size_t>(is.layer - 1)];
      break;
    case Issue::Where::param:
      p = p / "parameters" / layer_index[static_cast<std::size_t>(is.layer - 1)] / "params" /
          is.index / is.field;
      break;
    case Issue::Where::curve:
      p = p / "curves" / is.index / is.field;
      break;
    case Issue::Where::ct_entry:
      p = p / "command_table" / is.index / is.field;
      break;
    case Issue::Where::devicenet:
      p = p / "devicenet" / is.field;
      break;
    case Issue::Where::devicenet_value:
      p = p / "devicenet" / (is.live ? "live" : "values") / is.index / is.field;
      break;
  }
  return p;
}

// parameters (required): one object per layer around the table's fields;
// layer_index: where each layer is in the array.
Result<void> read_parameters(const JsonReader& r, const json& doc, DriveConfig& cfg,
                             LayerIndex& layer_index) {
  const Ptr root;
  const Ptr p = root / "parameters";
  LMCFG_ASSIGN_OR_RETURN(const json* pj, r.member(doc, root, "parameters", true));
  LMCFG_TRY(r.array(*pj, p));
  std::array<bool, lmcfg::layers::kCount> seen{};
  for (std::size_t li = 0; li < pj->size(); ++li) {
    const Ptr lp = p / li;
    const json& lj = (*pj)[li];
    LMCFG_TRY(r.object(lj, lp));
    LMCFG_TRY(r.keys(lj, lp, {"layer", "name", "params"}));
    LMCFG_ASSIGN_OR_RETURN(const json* nj, r.member(lj, lp, "layer", true));
    LMCFG_ASSIGN_OR_RETURN(auto l, r.unsigned_int(*nj, lp / "layer", 4, "a layer number"));
    if (l < 1)
      return r.err(Errc::parse_error, lp / "layer", "expected a layer number (1..4), found 0");
    if (seen[l - 1])
      return r.err(Errc::validation_failed, lp / "layer",
                   "layer " + std::to_string(l) + " appears twice");
    seen[l - 1] = true;
    layer_index[l - 1] = li;
    std::string ignored_name;
    LMCFG_TRY(r.opt_string(lj, lp, "name", ignored_name));
    LMCFG_ASSIGN_OR_RETURN(const json* arr, r.member(lj, lp, "params", true));
    LMCFG_TRY(r.array(*arr, lp / "params"));
    auto& out = cfg.layer(static_cast<int>(l));
    out.reserve(arr->size());
    for (std::size_t i = 0; i < arr->size(); ++i) {
      Parameter prm;
      LMCFG_TRY(r.read_record((*arr)[i], lp / "params" / i, fields::parameter_fields(), prm));
      out.push_back(std::move(prm));
    }
  }
  return {};
}

// curves, command_table (optional): arrays of records, each with an optional
// "decoded" object (derived: checked to be an object, not read).
template <class R>
Result<void> read_records(const JsonReader& r, const json& doc, const char* key,
                          std::span<const fields::Field<R>> table, std::vector<R>& out) {
  const Ptr root;
  const Ptr p = root / key;
  LMCFG_ASSIGN_OR_RETURN(const json* arr, r.member(doc, root, key, false));
  if (!arr) return {};
  LMCFG_TRY(r.array(*arr, p));
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const Ptr ip = p / i;
    const json& e = (*arr)[i];
    R rec;
    LMCFG_TRY(r.read_record(e, ip, table, rec, {"decoded"}));
    LMCFG_ASSIGN_OR_RETURN(const json* dec, r.member(e, ip, "decoded", false));
    if (dec) LMCFG_TRY(r.object(*dec, ip / "decoded"));
    out.push_back(std::move(rec));
  }
  return {};
}

// Versions 2 and 3: a version 2 file is a version 3 file without `devicenet`.
Result<DriveConfig> read_v2(const JsonReader& r, const json& doc, std::int64_t version) {
  const Ptr root;
  if (version < 3 && doc.contains("devicenet"))
    return r.err(Errc::parse_error, root / "devicenet",
                 "unexpected member; the devicenet section is new in format_version 3, this "
                 "file says " +
                     std::to_string(version));
  LMCFG_TRY(r.keys(doc, root,
                   {"format", "format_version", "identity", "scope", "parameters", "curves",
                    "command_table", "devicenet"}));
  DriveConfig cfg;
  LMCFG_ASSIGN_OR_RETURN(const json* idj, r.member(doc, root, "identity", false));
  if (idj)
    LMCFG_TRY(r.read_record(*idj, root / "identity", fields::identity_fields(), cfg.identity));
  LMCFG_ASSIGN_OR_RETURN(const json* sj, r.member(doc, root, "scope", true));
  LMCFG_TRY(r.read_record(*sj, root / "scope", fields::scope_fields(), cfg.scope));
  LayerIndex layer_index{};
  LMCFG_TRY(read_parameters(r, doc, cfg, layer_index));
  LMCFG_TRY(read_records(r, doc, "curves", fields::curve_fields(), cfg.curves));
  LMCFG_TRY(read_records(r, doc, "command_table", fields::ct_entry_fields(), cfg.ct_entries));
  LMCFG_ASSIGN_OR_RETURN(const json* dj, r.member(doc, root, "devicenet", false));
  if (dj) {
    DevicenetSection dn;
    LMCFG_TRY(r.read_record(*dj, root / "devicenet", fields::devicenet_fields(), dn));
    cfg.devicenet = std::move(dn);
  }
  if (auto is = find_issue(cfg))
    return r.err(Errc::validation_failed, issue_pointer(*is, layer_index), is->message);
  canonicalize(cfg);
  return cfg;
}

Result<DriveConfig> read_document(JsonReader& r, const json& doc) {
  const Ptr root;
  LMCFG_TRY(r.object(doc, root));
  LMCFG_ASSIGN_OR_RETURN(const json* fmt, r.member(doc, root, "format", true));
  LMCFG_ASSIGN_OR_RETURN(auto fmt_s, r.string(*fmt, root / "format"));
  LMCFG_TRY(detail::check_format_id(fmt_s, r.loc(root / "format")));
  LMCFG_ASSIGN_OR_RETURN(const json* ver, r.member(doc, root, "format_version", true));
  LMCFG_ASSIGN_OR_RETURN(auto version,
                         r.signed_int(*ver, root / "format_version", "an integer format version"));
  LMCFG_TRY(detail::check_format_version(version, r.name(), r.loc(root / "format_version")));
  r.set_version(version);
  if (version == 1) {
    LMCFG_ASSIGN_OR_RETURN(auto v1, detail::read_json_v1(r, doc));
    return migrate_v1_to_v2(v1);
  }
  return read_v2(r, doc, version);
}

}  // namespace

Result<DriveConfig> read_json(std::string_view text, std::string_view name) {
  json doc;
  try {
    doc = json::parse(text.begin(), text.end());
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 5: syntax error ..."
    if (auto col = what.find("column "); col != std::string::npos) {
      if (auto colon = what.find(": ", col); colon != std::string::npos)
        what = what.substr(colon + 2);
    }
    const std::size_t off = e.byte == 0 ? 0 : e.byte - 1;
    const auto pos = text_position(text, off);
    return Error(Errc::parse_error, std::string(name) + ":" + std::to_string(pos.line) + ":" +
                                        std::to_string(pos.column) + ": " + what);
  } catch (const json::out_of_range& e) {
    // A number no double can hold (found by fuzz_json_config): nlohmann names
    // the token but not its place, so locate the token's first occurrence.
    std::string what = e.what();
    std::string token;
    if (auto q = what.find('\''); q != std::string::npos) {
      if (auto q2 = what.find('\'', q + 1); q2 != std::string::npos)
        token = what.substr(q + 1, q2 - q - 1);
    }
    const auto at = token.empty() ? std::string_view::npos : text.find(token);
    const auto pos = text_position(text, at == std::string_view::npos ? 0 : at);
    std::string shown = token.size() > 24 ? token.substr(0, 24) + "..." : token;
    return Error(Errc::parse_error, std::string(name) + ":" + std::to_string(pos.line) + ":" +
                                        std::to_string(pos.column) + ": number " + shown +
                                        " is out of range (expected an integer value field)");
  }
  detail::JsonReader r(text, name);
  return read_document(r, doc);
}

Result<DriveConfig> read_json_file(const std::filesystem::path& path) {
  LMCFG_ASSIGN_OR_RETURN(auto text, read_text_file(path));
  return read_json(text, path.string());
}

}  // namespace lmcfg::config
