#pragma once
// Internal to lib/config: the XML reader's checks with located messages
// ("file: /lmcfg/parameters/layer[2]/param[3]/@value: what was expected") and
// the walkers of the field tables (fields.hpp) for XML. Not a public API.
#include <initializer_list>
#include <pugixml.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "config/fields.hpp"
#include "config/migrate.hpp"

namespace lmcfg::config::detail {

using pugi::xml_node;

// "/lmcfg/parameters/layer[2]/param[3]": repeated elements with their index.
std::string node_path(xml_node n);

class XmlReader {
 public:
  explicit XmlReader(std::string_view name) : name_(name) {}

  // The file's format_version, once known: fields newer than it are refused.
  void set_version(std::int64_t v) { version_ = v; }
  const std::string& name() const { return name_; }

  Error err(Errc e, xml_node n, const std::string& msg) const;
  Error err_attr(Errc e, xml_node n, std::string_view attr, const std::string& msg) const;
  std::string where(xml_node n) const { return name_ + ": " + node_path(n); }

  // Only the listed attributes and child elements; no text besides blanks.
  Result<void> shape(xml_node n, std::span<const std::string_view> attrs,
                     std::span<const std::string_view> children) const;
  Result<void> shape(xml_node n, std::initializer_list<std::string_view> attrs,
                     std::initializer_list<std::string_view> children) const {
    return shape(n, std::span<const std::string_view>(attrs.begin(), attrs.size()),
                 std::span<const std::string_view>(children.begin(), children.size()));
  }
  // The single child element `name` (null when absent and optional).
  Result<xml_node> single(xml_node n, const char* name, bool required) const;
  Result<std::string> attr(xml_node n, const char* name, bool required) const;
  Result<std::uint64_t> uint_attr(xml_node n, const char* name, std::uint64_t max,
                                  std::string_view what) const;
  Result<std::int64_t> int_attr(xml_node n, const char* name, std::string_view what) const;
  Result<bool> bool_attr(xml_node n, const char* name) const;
  // Text of an element holding only text.
  Result<std::string> text(xml_node n, std::initializer_list<std::string_view> attrs = {}) const;
  Result<void> opt_text(xml_node parent, const char* name, std::string& out) const;
  Result<Bytes> rows(xml_node n) const;

  // One field of the record element `n` (not a group).
  Result<void> read_value(xml_node n, const fields::Spec& s, const fields::Ref& ref) const;

  // The record element `n`: the table's attributes and elements (and the
  // `extra` elements, read by the caller), into `rec`.
  template <class R>
  Result<void> read_record(xml_node n, std::span<const fields::Field<R>> table, R& rec,
                           std::initializer_list<std::string_view> extra = {}) const {
    std::vector<std::string_view> attrs, children;
    for (const auto& f : table)
      (fields::xml_element(f.spec) ? children : attrs).push_back(f.spec.key);
    children.insert(children.end(), extra.begin(), extra.end());
    LMCFG_TRY(shape(n, attrs, children));
    for (int phase = 0; phase < 3; ++phase) {
      for (const auto& f : table) {
        if (fields::read_phase(f.spec, true) != phase) continue;
        LMCFG_TRY(since(n, f.spec));
        if (f.spec.kind != fields::Kind::group) {
          LMCFG_TRY(read_value(n, f.spec, f.at(rec)));
          continue;
        }
        const std::string key(f.spec.key);
        LMCFG_ASSIGN_OR_RETURN(xml_node g, single(n, key.c_str(), false));
        if (g) LMCFG_TRY(read_record(g, f.group(), rec));
      }
    }
    return {};
  }

 private:
  Result<void> since(xml_node n, const fields::Spec& s) const;
  Result<void> read_element(xml_node n, const fields::Spec& s, const fields::Ref& ref) const;

  std::string name_;
  std::int64_t version_ = kFormatVersion;
};

// A format version 1 document (xml_read_v1.cpp; its layout is frozen, not in
// the field tables).
Result<ConfigV1> read_xml_v1(const XmlReader& r, xml_node root);

// One field of a record into the element `n` (not a group).
void write_value(xml_node n, const fields::Spec& s, const fields::Ref& ref);

// The record's attributes and elements into `n`, in the table's write order.
template <class R>
void write_record(xml_node n, std::span<const fields::Field<R>> table, const R& rec) {
  auto& r = const_cast<R&>(rec);  // accessors hand out references; nothing is written
  for (const auto* f : fields::write_order(table)) {
    if (f->spec.kind == fields::Kind::group)
      write_record(n.append_child(std::string(f->spec.key).c_str()), f->group(), rec);
    else
      write_value(n, f->spec, f->at(r));
  }
}

}  // namespace lmcfg::config::detail
