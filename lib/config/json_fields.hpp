#pragma once
// Internal to lib/config: the JSON reader's checks with located messages
// ("file:line:column: /json/pointer: what was expected") and the walkers of
// the field tables (fields.hpp) for JSON. Not a public API.
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "config/fields.hpp"
#include "config/migrate.hpp"

namespace lmcfg::config::detail {

using json = nlohmann::json;
using ojson = nlohmann::ordered_json;

// A JSON pointer under construction: Ptr{} / "curves" / 0 / "id".
struct Ptr {
  std::vector<std::string> tokens;
  Ptr operator/(std::string_view key) const;
  Ptr operator/(std::size_t index) const;
  std::string str() const;  // "/curves/0/id", "/" for the root
};

// "number 7", "string \"x\"" (cut after 40 characters), "object", ...
std::string describe(const json& j);

class JsonReader {
 public:
  JsonReader(std::string_view text, std::string_view name) : text_(text), name_(name) {}

  // The file's format_version, once known: fields newer than it are refused.
  void set_version(std::int64_t v) { version_ = v; }
  const std::string& name() const { return name_; }

  Error err(Errc e, const Ptr& p, const std::string& msg) const;
  // "name:line:column: /pointer", the pointer located in the text.
  std::string loc(const Ptr& p) const;

  // Only the `allowed` members.
  Result<void> keys(const json& obj, const Ptr& p, std::span<const std::string_view> allowed) const;
  Result<void> keys(const json& obj, const Ptr& p,
                    std::initializer_list<std::string_view> allowed) const {
    return keys(obj, p, std::span<const std::string_view>(allowed.begin(), allowed.size()));
  }
  // The member `key` (nullptr when absent and not required).
  Result<const json*> member(const json& obj, const Ptr& p, std::string_view key,
                             bool required) const;
  Result<const json*> object(const json& j, const Ptr& p) const;
  Result<const json*> array(const json& j, const Ptr& p) const;
  Result<std::string> string(const json& j, const Ptr& p) const;
  Result<bool> boolean(const json& j, const Ptr& p) const;
  Result<std::uint64_t> unsigned_int(const json& j, const Ptr& p, std::uint64_t max,
                                     std::string_view what) const;
  Result<std::int64_t> signed_int(const json& j, const Ptr& p, std::string_view what) const;
  Result<Bytes> rows(const json& j, const Ptr& p) const;
  // Optional string member into `out`.
  Result<void> opt_string(const json& obj, const Ptr& p, std::string_view key,
                          std::string& out) const;

  // One field of the record object `obj` at `p` (not a group).
  Result<void> read_value(const json& obj, const Ptr& p, const fields::Spec& s,
                          const fields::Ref& ref) const;

  // The fields of `rec` from the members of `obj` (without checking for others).
  template <class R>
  Result<void> read_fields(const json& obj, const Ptr& p, std::span<const fields::Field<R>> table,
                           R& rec) const {
    for (int phase = 0; phase < 3; ++phase) {
      for (const auto& f : table) {
        if (fields::read_phase(f.spec, false) != phase) continue;
        LMCFG_TRY(since(obj, p, f.spec));
        if (f.spec.kind != fields::Kind::group) {
          LMCFG_TRY(read_value(obj, p, f.spec, f.at(rec)));
          continue;
        }
        LMCFG_ASSIGN_OR_RETURN(const json* g, member(obj, p, f.spec.key, false));
        if (g) LMCFG_TRY(read_record(*g, p / f.spec.key, f.group(), rec));
      }
    }
    return {};
  }

  // The record at `p`: an object with the table's members (and `extra`, read
  // by the caller), into `rec`.
  template <class R>
  Result<void> read_record(const json& j, const Ptr& p, std::span<const fields::Field<R>> table,
                           R& rec, std::initializer_list<std::string_view> extra = {}) const {
    LMCFG_TRY(object(j, p));
    std::vector<std::string_view> allowed;
    for (const auto& f : table) allowed.push_back(f.spec.key);
    allowed.insert(allowed.end(), extra.begin(), extra.end());
    LMCFG_TRY(keys(j, p, allowed));
    return read_fields(j, p, table, rec);
  }

 private:
  Result<void> since(const json& obj, const Ptr& p, const fields::Spec& s) const;
  Result<void> read_list(const json& j, const Ptr& p, const fields::Spec& s,
                         const fields::Ref& ref) const;

  std::string_view text_;
  std::string name_;
  std::int64_t version_ = kFormatVersion;
};

// A format version 1 document (json_read_v1.cpp; its layout is frozen, not in
// the field tables).
Result<ConfigV1> read_json_v1(const JsonReader& r, const json& doc);

// One field of a record into `out` (not a group).
void write_value(ojson& out, const fields::Spec& s, const fields::Ref& ref);

// The record as a JSON object, its members in the table's write order.
template <class R>
ojson write_record(std::span<const fields::Field<R>> table, const R& rec) {
  ojson out = ojson::object();
  auto& r = const_cast<R&>(rec);  // accessors hand out references; nothing is written
  for (const auto* f : fields::write_order(table)) {
    if (f->spec.kind == fields::Kind::group)
      out[std::string(f->spec.key)] = write_record(f->group(), rec);
    else
      write_value(out, f->spec, f->at(r));
  }
  return out;
}

}  // namespace lmcfg::config::detail
