#include "ops/param_info.hpp"

namespace lmcfg::ops {

namespace {

void add(std::string& asked, const std::string& what) {
  asked += (asked.empty() ? "" : ", ") + what;
}

}  // namespace

Result<ParamDescription> describe_parameter(client::Client& c, std::uint16_t upid,
                                            const db::Parameter* known, bool with_range) {
  ParamDescription out;
  if (known) out.spec = known->spec;
  db::ValueSpec& spec = out.spec;
  if (!spec.type) {
    LMCFG_ASSIGN_OR_RETURN(auto t, unless_refused(c.get_type(upid)));
    if (t) {
      spec.type = db::type_from_code(*t);
      add(out.asked,
          "type " + (spec.type ? std::string(db::type_name(*spec.type)) : std::to_string(*t)));
    }
  }
  if (!with_range || !spec.type || db::is_text_type(*spec.type)) return out;
  // The drive sends limits in the 4-byte field; compare them as the type's integers.
  auto limit = [&](Result<std::uint32_t> r, const char* what,
                   std::optional<std::int64_t>& dst) -> Result<void> {
    LMCFG_ASSIGN_OR_RETURN(auto v, unless_refused(std::move(r)));
    if (!v) return {};
    const auto dv = db::decode_value(*spec.type, *v);
    dst = dv.kind == db::Value::Kind::Integer ? dv.integer : static_cast<std::int64_t>(*v);
    add(out.asked, what);
    return {};
  };
  if (!spec.min) LMCFG_TRY(limit(c.get_min(upid), "min", spec.min));
  if (!spec.max) LMCFG_TRY(limit(c.get_max(upid), "max", spec.max));
  return out;
}

}  // namespace lmcfg::ops
