#include "config/fields.hpp"

namespace lmcfg::config::fields {
namespace {

// The accessor of a direct member of R.
template <class R, auto M>
Ref member(R& r) {
  return &(r.*M);
}

constexpr std::uint64_t kU32 = 0xFFFFFFFFu;

// The file's fields, in the order the readers list them in messages and the
// writers write them (write_rank aside). Texts of the identity are elements of
// their own in XML; every other scalar is an attribute.
constexpr Field<Identity> kLink[] = {
    {{.key = "port"}, [](Identity& r) -> Ref { return &r.link.port; }},
    {{.key = "baud"}, [](Identity& r) -> Ref { return &r.link.baud; }},
    {{.key = "parity"}, [](Identity& r) -> Ref { return &r.link.parity; }},
    {{.key = "stop_bits"}, [](Identity& r) -> Ref { return &r.link.stop_bits; }},
    {{.key = "checksum"}, [](Identity& r) -> Ref { return &r.link.checksum; }},
};

constexpr Field<Identity> kUpidDb[] = {
    {{.key = "version"}, member<Identity, &Identity::upid_db_version>},
    {{.key = "hash"}, member<Identity, &Identity::upid_db_hash>},
};

constexpr Spec text_element(std::string_view key) { return {.key = key, .xml = Xml::element}; }

constexpr Field<Identity> kIdentity[] = {
    {text_element("macid"), member<Identity, &Identity::macid>},
    {{.key = "link", .kind = Kind::group}, nullptr, link_fields},
    {text_element("product"), member<Identity, &Identity::product>},
    {text_element("firmware"), member<Identity, &Identity::firmware>},
    {text_element("upid_fingerprint"), member<Identity, &Identity::upid_fingerprint>},
    {text_element("tool_version"), member<Identity, &Identity::tool_version>},
    {{.key = "upid_db", .kind = Kind::group}, nullptr, upid_db_fields},
    {text_element("captured_at"), member<Identity, &Identity::captured_at>},
    {{.key = "labels", .kind = Kind::label_map, .item = "label"},
     member<Identity, &Identity::labels>},
};

constexpr Field<Scope> kScope[] = {
    {{.key = "layers", .kind = Kind::layer_set, .use = Use::required},
     member<Scope, &Scope::layers>},
    {{.key = "parameters", .kind = Kind::param_set, .use = Use::required},
     member<Scope, &Scope::parameters>},
    {{.key = "curves", .kind = Kind::flag, .use = Use::required}, member<Scope, &Scope::curves>},
    {{.key = "command_table", .kind = Kind::flag, .use = Use::required},
     member<Scope, &Scope::command_table>},
    {{.key = "drive_lacks",
      .kind = Kind::text_list,
      .use = Use::nonempty,
      .item = "group",
      .since = 3},
     member<Scope, &Scope::drive_lacks>},
};

constexpr Field<Parameter> kParameter[] = {
    {{.key = "upid", .kind = Kind::upid, .use = Use::required},
     member<Parameter, &Parameter::upid>},
    {{.key = "value",
      .kind = Kind::number,
      .use = Use::required,
      .max = kU32,
      .what = "an unsigned 32-bit value"},
     member<Parameter, &Parameter::value>},
    {{.key = "type", .kind = Kind::number, .use = Use::nonempty, .max = 15, .what = "a type code"},
     member<Parameter, &Parameter::type>},
    {{.key = "default",
      .kind = Kind::number,
      .use = Use::nonempty,
      .max = kU32,
      .what = "an unsigned 32-bit value"},
     member<Parameter, &Parameter::default_value>},
    {{.key = "name", .use = Use::nonempty}, member<Parameter, &Parameter::name>},
    // Listed before "scaled" in messages, written after it.
    {{.key = "unit", .use = Use::nonempty, .write_rank = 1}, member<Parameter, &Parameter::unit>},
    {{.key = "scaled", .use = Use::nonempty}, member<Parameter, &Parameter::scaled>},
};

constexpr Field<Curve> kCurve[] = {
    {{.key = "id", .kind = Kind::number, .use = Use::required, .max = 0xFFFF, .what = "a curve ID"},
     member<Curve, &Curve::id>},
    {{.key = "info", .kind = Kind::rows, .use = Use::required}, member<Curve, &Curve::info>},
    {{.key = "data", .kind = Kind::rows, .use = Use::required}, member<Curve, &Curve::data>},
};

constexpr Field<CtEntry> kCtEntry[] = {
    {{.key = "id", .kind = Kind::number, .use = Use::required, .max = kU32, .what = "an entry ID"},
     member<CtEntry, &CtEntry::id>},
    {{.key = "raw", .kind = Kind::rows, .use = Use::required}, member<CtEntry, &CtEntry::raw>},
};

constexpr Field<DevicenetSection> kDevicenet[] = {
    {{.key = "can_bitrate",
      .kind = Kind::number,
      .use = Use::required,
      .max = kU32,
      .what = "a CAN bit rate",
      .since = 3},
     member<DevicenetSection, &DevicenetSection::can_bitrate>},
    {{.key = "io_modules", .kind = Kind::text_list, .item = "module", .since = 3},
     member<DevicenetSection, &DevicenetSection::io_modules>},
    {{.key = "motors", .kind = Kind::motor_list, .use = Use::required, .since = 3},
     member<DevicenetSection, &DevicenetSection::motors>},
    {{.key = "values", .kind = Kind::value_list, .item = "value", .since = 3},
     member<DevicenetSection, &DevicenetSection::values>},
    {{.key = "live", .kind = Kind::value_list, .item = "value", .since = 3},
     member<DevicenetSection, &DevicenetSection::live>},
};

constexpr Field<DevicenetValue> kDevicenetValue[] = {
    {{.key = "motor", .kind = Kind::motor, .use = Use::required, .since = 3},
     member<DevicenetValue, &DevicenetValue::motor>},
    {{.key = "command", .kind = Kind::command, .use = Use::required, .since = 3},
     member<DevicenetValue, &DevicenetValue::command>},
    {{.key = "raw",
      .kind = Kind::number,
      .use = Use::required,
      .max = 0xFFFF,
      .what = "a 16-bit word",
      .since = 3},
     member<DevicenetValue, &DevicenetValue::raw>},
    {{.key = "name", .use = Use::nonempty, .since = 3},
     member<DevicenetValue, &DevicenetValue::name>},
    {{.key = "scaled", .use = Use::nonempty, .since = 3},
     member<DevicenetValue, &DevicenetValue::scaled>},
    {{.key = "unit", .use = Use::nonempty, .since = 3},
     member<DevicenetValue, &DevicenetValue::unit>},
};

}  // namespace

std::span<const Field<Identity>> identity_fields() { return kIdentity; }
std::span<const Field<Identity>> link_fields() { return kLink; }
std::span<const Field<Identity>> upid_db_fields() { return kUpidDb; }
std::span<const Field<Scope>> scope_fields() { return kScope; }
std::span<const Field<Parameter>> parameter_fields() { return kParameter; }
std::span<const Field<Curve>> curve_fields() { return kCurve; }
std::span<const Field<CtEntry>> ct_entry_fields() { return kCtEntry; }
std::span<const Field<DevicenetSection>> devicenet_fields() { return kDevicenet; }
std::span<const Field<DevicenetValue>> devicenet_value_fields() { return kDevicenetValue; }

}  // namespace lmcfg::config::fields
