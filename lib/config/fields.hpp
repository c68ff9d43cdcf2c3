#pragma once
// The one description of the file's fields: for each record of the model
// (identity, scope, parameter, curve, command table entry, DeviceNet section
// and value) a table of its fields, which the JSON reader and writer
// (json_fields.hpp) and the XML reader and writer (xml_fields.hpp) all walk.
// A new field of an existing kind is one row here (plus the model member and
// both schemas); a new kind is one case in each of the four walkers.
//
// The document's frame (format, format_version, the parameters' layer
// wrappers, the decoded views) is code in json_io.cpp/xml_io.cpp; the fields
// inside it are these tables. docs/config-files.md describes the result.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

#include "common/bytes.hpp"
#include "common/layers.hpp"
#include "config/model.hpp"

namespace lmcfg::config::fields {

// How a field is written: the encoding in both formats.
enum class Kind {
  text,        // std::string: JSON string; XML attribute, or element text (Xml::element)
  upid,        // std::uint16_t: "13A2", 4 hex digits
  number,      // unsigned integer 0..max (also std::optional): JSON number, XML decimal
  flag,        // bool: JSON true/false, XML "true"/"false"
  rows,        // Bytes: rows of up to 16 hex bytes; JSON array of strings, XML <row> elements
  motor,       // int: "controller" (kDevicenetController) or "A".."D" (0..3)
  command,     // std::uint8_t: DeviceNet command ID, 2 hex digits
  param_set,   // ParamSet: "modified" / "full"
  layer_set,   // std::array<bool, 4>: JSON array of layer numbers, XML "1 2 3"
  motor_list,  // std::vector<int>: JSON array of "A".."D", XML "A B"
  text_list,   // std::vector<std::string>: JSON array, XML element of `item` elements
  label_map,   // std::map<string, string>: JSON object, XML element of <`item` key="k">v</...>
  group,       // fields of the same record nested: JSON object, XML element with attributes
  value_list,  // std::vector<DevicenetValue>: array of records (devicenet_value_fields())
};

enum class Use {
  required,  // a reader refuses a file without it; always written
  optional,  // absent: the model's default; always written
  nonempty,  // absent: empty (or no value); written only when set / not empty
};

// Where a field sits in XML (JSON: always a member of the record's object).
enum class Xml { attribute, element };

// A reference to the model member a field reads and writes; the alternative
// must fit the kind (tests/config/test_fields.cpp checks every table).
using Ref = std::variant<std::string*, std::uint32_t*, std::uint16_t*, std::uint8_t*,
                         std::optional<std::uint8_t>*, std::optional<std::uint32_t>*, bool*, int*,
                         Bytes*, ParamSet*, std::array<bool, lmcfg::layers::kCount>*,
                         std::vector<int>*, std::vector<std::string>*,
                         std::map<std::string, std::string>*, std::vector<DevicenetValue>*>;

// What the walkers need of a field besides its member.
struct Spec {
  std::string_view key = {};  // JSON member name, XML attribute or element name
  Kind kind = Kind::text;
  Use use = Use::optional;
  std::uint64_t max = 0;       // number: largest value
  std::string_view what = {};  // number: what it is, in messages ("a curve ID")
  Xml xml = Xml::attribute;    // rows, text_list, label_map, group, value_list: always elements
  std::string_view item = {};  // text_list, label_map, value_list: the XML item element
  int since = 2;               // the format_version that introduced it
  int write_rank = 0;          // written after the fields of a lower rank (table order within)
};

template <class R>
struct Field {
  Spec spec;
  Ref (*at)(R&) = nullptr;                         // the member (not for groups)
  std::span<const Field<R>> (*group)() = nullptr;  // Kind::group: the nested fields
};

// Whether a field sits in an XML element of its own (else an attribute).
constexpr bool xml_element(const Spec& s) noexcept {
  switch (s.kind) {
    case Kind::rows:
    case Kind::text_list:
    case Kind::label_map:
    case Kind::group:
    case Kind::value_list:
      return true;
    default:
      return s.xml == Xml::element;
  }
}

// The order readers take fields in (0 first, table order within): XML
// attributes, then plain members and elements, then nested groups and maps.
constexpr int read_phase(const Spec& s, bool xml) noexcept {
  if (s.kind == Kind::group || s.kind == Kind::label_map) return 2;
  return xml && !xml_element(s) ? 0 : 1;
}

// The fields in the order writers write them (stable by write_rank).
template <class R>
std::vector<const Field<R>*> write_order(std::span<const Field<R>> fields) {
  std::vector<const Field<R>*> out;
  for (int rank = 0; out.size() < fields.size(); ++rank)
    for (const auto& f : fields)
      if (f.spec.write_rank == rank) out.push_back(&f);
  return out;
}

// Kind::number: the member's value; nullopt for an empty std::optional.
inline std::optional<std::uint64_t> number_of(const Ref& ref) {
  return std::visit(
      [](auto* m) -> std::optional<std::uint64_t> {
        using T = std::remove_pointer_t<decltype(m)>;
        if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
          return static_cast<std::uint64_t>(*m);
        } else if constexpr (requires { m->has_value(); }) {
          if (*m) return static_cast<std::uint64_t>(**m);
          return std::nullopt;
        } else {
          return std::nullopt;
        }
      },
      ref);
}
// Kind::number: stores a value the reader checked against Spec::max.
inline void set_number(const Ref& ref, std::uint64_t v) {
  std::visit(
      [v](auto* m) {
        using T = std::remove_pointer_t<decltype(m)>;
        if constexpr (std::is_integral_v<T> && !std::is_same_v<T, bool>) {
          *m = static_cast<T>(v);
        } else if constexpr (requires {
                               typename T::value_type;
                               m->has_value();
                             }) {
          *m = static_cast<typename T::value_type>(v);
        }
      },
      ref);
}

// The tables.
std::span<const Field<Identity>> identity_fields();
std::span<const Field<Identity>> link_fields();     // identity/link
std::span<const Field<Identity>> upid_db_fields();  // identity/upid_db
std::span<const Field<Scope>> scope_fields();
std::span<const Field<Parameter>> parameter_fields();
std::span<const Field<Curve>> curve_fields();
std::span<const Field<CtEntry>> ct_entry_fields();
std::span<const Field<DevicenetSection>> devicenet_fields();
std::span<const Field<DevicenetValue>> devicenet_value_fields();

// The first text field (groups included, as "group.key") of `rec` that is not
// clean text (model.hpp is_clean_text), for validation; nullopt when all are.
template <class R>
std::optional<std::string> unclean_text(std::span<const Field<R>> fields, const R& rec) {
  for (const auto& f : fields) {
    if (f.spec.kind == Kind::group) {
      if (auto bad = unclean_text(f.group(), rec)) return std::string(f.spec.key) + "." + *bad;
    } else if (f.spec.kind == Kind::text) {
      const std::string* s = std::get<std::string*>(f.at(const_cast<R&>(rec)));
      if (!is_clean_text(*s)) return std::string(f.spec.key);
    }
  }
  return std::nullopt;
}

}  // namespace lmcfg::config::fields
