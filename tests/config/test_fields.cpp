// The field tables (lib/config/fields.cpp) and the walkers of both formats
// (json_fields.hpp, xml_fields.hpp): every field of every table round-trips
// through JSON and XML on its own, every member of the model is in a table,
// and a record described by a table of its own needs no other code.
#include <catch2/catch.hpp>
#include <set>
#include <sstream>

#include "config/fields.hpp"
#include "config/json_fields.hpp"
#include "config/xml_fields.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_fields {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::fields;
using lmcfg::config::detail::JsonReader;
using lmcfg::config::detail::Ptr;
using lmcfg::config::detail::XmlReader;

namespace {

// Whether the member a field points at is of the type its kind encodes.
bool fits(Kind kind, const Ref& ref) {
  switch (kind) {
    case Kind::text:
      return std::holds_alternative<std::string*>(ref);
    case Kind::upid:
      return std::holds_alternative<std::uint16_t*>(ref);
    case Kind::number:
      return std::visit(
          [](auto* m) {
            using T = std::remove_pointer_t<decltype(m)>;
            return (std::is_integral_v<T> && !std::is_same_v<T, bool>) ||
                   std::is_same_v<T, std::optional<std::uint8_t>> ||
                   std::is_same_v<T, std::optional<std::uint32_t>>;
          },
          ref);
    case Kind::flag:
      return std::holds_alternative<bool*>(ref);
    case Kind::rows:
      return std::holds_alternative<Bytes*>(ref);
    case Kind::motor:
      return std::holds_alternative<int*>(ref);
    case Kind::command:
      return std::holds_alternative<std::uint8_t*>(ref);
    case Kind::param_set:
      return std::holds_alternative<ParamSet*>(ref);
    case Kind::layer_set:
      return std::holds_alternative<std::array<bool, lmcfg::layers::kCount>*>(ref);
    case Kind::motor_list:
      return std::holds_alternative<std::vector<int>*>(ref);
    case Kind::text_list:
      return std::holds_alternative<std::vector<std::string>*>(ref);
    case Kind::label_map:
      return std::holds_alternative<std::map<std::string, std::string>*>(ref);
    case Kind::value_list:
      return std::holds_alternative<std::vector<DevicenetValue>*>(ref);
    case Kind::group:
      return false;
  }
  return false;
}

// A value of the field's kind that differs from every member's default.
void probe(const Spec& s, const Ref& ref) {
  switch (s.kind) {
    case Kind::text:
      *std::get<std::string*>(ref) = "probe & <\"ü\">";
      return;
    case Kind::upid:
      *std::get<std::uint16_t*>(ref) = 0x13A2;
      return;
    case Kind::number:
      set_number(ref, std::min<std::uint64_t>(s.max, 12345));
      return;
    case Kind::flag:
      *std::get<bool*>(ref) = !*std::get<bool*>(ref);
      return;
    case Kind::rows:
      *std::get<Bytes*>(ref) = Bytes{0x46, 0,    3,    0,    0x15, 0,    4, 0,   0x53,
                                     0x69, 0x6E, 0x52, 0x69, 0x73, 0x65, 0, 0xFF};  // two rows
      return;
    case Kind::motor:
      *std::get<int*>(ref) = 2;
      return;
    case Kind::command:
      *std::get<std::uint8_t*>(ref) = 0x34;
      return;
    case Kind::param_set:
      *std::get<ParamSet*>(ref) = ParamSet::full;
      return;
    case Kind::layer_set:
      *std::get<std::array<bool, lmcfg::layers::kCount>*>(ref) = {false, true, false, true};
      return;
    case Kind::motor_list:
      *std::get<std::vector<int>*>(ref) = {0, 3};
      return;
    case Kind::text_list:
      *std::get<std::vector<std::string>*>(ref) = {"control-in", "status-out"};
      return;
    case Kind::label_map:
      *std::get<std::map<std::string, std::string>*>(ref) = {{"axis", "X"}, {"empty", ""}};
      return;
    case Kind::value_list:
      *std::get<std::vector<DevicenetValue>*>(ref) = {{1, 0x34, 7, "n", "u", "s"},
                                                      {kDevicenetController, 2, 0, "", "", ""}};
      return;
    case Kind::group:
      return;
  }
}

std::string xml_of(const pugi::xml_document& d) {
  std::ostringstream o;
  d.save(o, "  ", pugi::format_indent | pugi::format_no_declaration, pugi::encoding_utf8);
  return o.str();
}

template <class R>
R json_round_trip(std::span<const Field<R>> table, const R& rec) {
  const std::string text = detail::write_record(table, rec).dump(2);
  JsonReader reader(text, "t.json");
  R back{};
  const auto r = reader.read_record(nlohmann::json::parse(text), Ptr{}, table, back);
  INFO(text);
  INFO((r.ok() ? std::string() : r.error().message));
  REQUIRE(r.ok());
  return back;
}

template <class R>
R xml_round_trip(std::span<const Field<R>> table, const R& rec) {
  pugi::xml_document out;
  detail::write_record(out.append_child("record"), table, rec);
  const std::string text = xml_of(out);
  pugi::xml_document in;
  REQUIRE(in.load_string(text.c_str()));
  XmlReader reader("t.xml");
  R back{};
  const auto r = reader.read_record(in.document_element(), table, back);
  INFO(text);
  INFO((r.ok() ? std::string() : r.error().message));
  REQUIRE(r.ok());
  return back;
}

// Each field of the table probed alone: written differently from the default
// record, read back to the same record, in both formats.
template <class R>
void check_each_field(std::span<const Field<R>> table, std::span<const Field<R>> top, int& count) {
  for (const auto& f : table) {
    INFO(std::string(f.spec.key));
    if (f.spec.kind == Kind::group) {
      check_each_field(f.group(), top, count);
      continue;
    }
    R plain{};
    R rec{};
    CHECK(fits(f.spec.kind, f.at(rec)));
    probe(f.spec, f.at(rec));
    REQUIRE_FALSE(rec == plain);
    CHECK(detail::write_record(top, rec) != detail::write_record(top, plain));
    CHECK(json_round_trip(top, rec) == rec);
    CHECK(xml_round_trip(top, rec) == rec);
    ++count;
  }
}

// The members the table reaches (addresses within `rec`).
template <class R>
std::set<const void*> reached(std::span<const Field<R>> table, R& rec) {
  std::set<const void*> out;
  for (const auto& f : table) {
    if (f.spec.kind == Kind::group) {
      auto sub = reached(f.group(), rec);
      out.insert(sub.begin(), sub.end());
    } else {
      out.insert(std::visit([](auto* m) { return static_cast<const void*>(m); }, f.at(rec)));
    }
  }
  return out;
}

}  // namespace

TEST_CASE("fields: every field of every table round-trips alone through JSON and XML",
          "[config][fields]") {
  int count = 0;
  check_each_field(identity_fields(), identity_fields(), count);
  check_each_field(scope_fields(), scope_fields(), count);
  check_each_field(parameter_fields(), parameter_fields(), count);
  check_each_field(curve_fields(), curve_fields(), count);
  check_each_field(ct_entry_fields(), ct_entry_fields(), count);
  check_each_field(devicenet_fields(), devicenet_fields(), count);
  check_each_field(devicenet_value_fields(), devicenet_value_fields(), count);
  CHECK(count == 14 + 5 + 7 + 3 + 2 + 5 + 6);
}

// A structured binding names every member of a record: a member added to the
// model stops this test from compiling until it is listed here, and then it
// fails until a table reaches it.
TEST_CASE("fields: the tables reach every member of the model", "[config][fields]") {
  Identity id;
  auto& [macid, link, product, firmware, fingerprint, tool, db_version, db_hash, captured, labels] =
      id;
  auto& [port, baud, parity, stop_bits, checksum] = link;
  const auto in_identity = reached(identity_fields(), id);
  for (const void* m :
       {(const void*)&macid, (const void*)&product, (const void*)&firmware,
        (const void*)&fingerprint, (const void*)&tool, (const void*)&db_version,
        (const void*)&db_hash, (const void*)&captured, (const void*)&labels, (const void*)&port,
        (const void*)&baud, (const void*)&parity, (const void*)&stop_bits, (const void*)&checksum})
    CHECK(in_identity.count(m) == 1);
  CHECK(in_identity.size() == 14);

  Scope scope;
  auto& [layers, parameters, curves, command_table, drive_lacks] = scope;
  CHECK(reached(scope_fields(), scope) ==
        std::set<const void*>{&layers, &parameters, &curves, &command_table, &drive_lacks});

  Parameter p;
  auto& [upid, value, type, dflt, name, unit, scaled] = p;
  CHECK(reached(parameter_fields(), p) ==
        std::set<const void*>{&upid, &value, &type, &dflt, &name, &unit, &scaled});

  Curve c;
  auto& [curve_id, info, data] = c;
  CHECK(reached(curve_fields(), c) == std::set<const void*>{&curve_id, &info, &data});

  CtEntry e;
  auto& [entry_id, raw] = e;
  CHECK(reached(ct_entry_fields(), e) == std::set<const void*>{&entry_id, &raw});

  DevicenetSection dn;
  auto& [bitrate, modules, motors, values, live] = dn;
  CHECK(reached(devicenet_fields(), dn) ==
        std::set<const void*>{&bitrate, &modules, &motors, &values, &live});

  DevicenetValue v;
  auto& [motor, command, word, vname, vunit, vscaled] = v;
  CHECK(reached(devicenet_value_fields(), v) ==
        std::set<const void*>{&motor, &command, &word, &vname, &vunit, &vscaled});
}

TEST_CASE("fields: writers follow the table order, write_rank last", "[config][fields]") {
  const auto order = write_order(parameter_fields());
  std::string keys;
  for (const auto* f : order) keys += std::string(f->spec.key) + " ";
  CHECK(keys == "upid value type default name scaled unit ");
  CHECK(read_phase(Spec{.key = "link", .kind = Kind::group}, false) == 2);
  CHECK(read_phase(Spec{.key = "id", .kind = Kind::number}, true) == 0);
  CHECK(read_phase(Spec{.key = "macid", .xml = Xml::element}, true) == 1);
}

// --------------------------------------------------------------------------
// A record that is not in the model: its table is all the code it takes to be
// read and written in both formats, with the readers' located messages.
namespace {

struct Gadget {
  std::string label;
  std::uint32_t count = 0;
  std::optional<std::uint8_t> level;
  Bytes blob;
  bool armed = false;
  std::string note;  // appeared in format_version 3
  bool operator==(const Gadget&) const = default;
};

constexpr Field<Gadget> kGadget[] = {
    {{.key = "label", .xml = Xml::element}, [](Gadget& g) -> Ref { return &g.label; }},
    {{.key = "count", .kind = Kind::number, .use = Use::required, .max = 1000, .what = "a count"},
     [](Gadget& g) -> Ref { return &g.count; }},
    {{.key = "level", .kind = Kind::number, .use = Use::nonempty, .max = 9, .what = "a level"},
     [](Gadget& g) -> Ref { return &g.level; }},
    {{.key = "blob", .kind = Kind::rows, .use = Use::required},
     [](Gadget& g) -> Ref { return &g.blob; }},
    {{.key = "armed", .kind = Kind::flag, .use = Use::required},
     [](Gadget& g) -> Ref { return &g.armed; }},
    {{.key = "note", .use = Use::nonempty, .since = 3}, [](Gadget& g) -> Ref { return &g.note; }},
};

std::span<const Field<Gadget>> gadget_fields() { return kGadget; }

Result<Gadget> gadget_from_json(std::string_view text, std::int64_t version = 3) {
  JsonReader r(text, "g.json");
  r.set_version(version);
  Gadget g;
  LMCFG_TRY(r.read_record(nlohmann::json::parse(text), Ptr{}, gadget_fields(), g));
  return g;
}

Result<Gadget> gadget_from_xml(const std::string& text, std::int64_t version = 3) {
  pugi::xml_document d;
  REQUIRE(d.load_string(text.c_str()));
  XmlReader r("g.xml");
  r.set_version(version);
  Gadget g;
  LMCFG_TRY(r.read_record(d.document_element(), gadget_fields(), g));
  return g;
}

}  // namespace

TEST_CASE("fields: a record described by a table alone is read and written in both formats",
          "[config][fields]") {
  const Gadget g{"first & <only>", 7, 3, Bytes(20, 0xAB), true, "n"};
  const std::string json = detail::write_record(gadget_fields(), g).dump();
  CHECK(json ==
        "{\"label\":\"first & <only>\",\"count\":7,\"level\":3,\"blob\":[\"AB AB AB AB AB AB AB "
        "AB AB AB AB AB AB AB AB AB\",\"AB AB AB AB\"],\"armed\":true,\"note\":\"n\"}");
  CHECK(*gadget_from_json(json) == g);
  pugi::xml_document d;
  detail::write_record(d.append_child("gadget"), gadget_fields(), g);
  const std::string xml = xml_of(d);
  CHECK(xml ==
        "<gadget count=\"7\" level=\"3\" armed=\"true\" note=\"n\">\n"
        "  <label>first &amp; &lt;only&gt;</label>\n"
        "  <blob>\n"
        "    <row>AB AB AB AB AB AB AB AB AB AB AB AB AB AB AB AB</row>\n"
        "    <row>AB AB AB AB</row>\n"
        "  </blob>\n"
        "</gadget>\n");
  CHECK(*gadget_from_xml(xml) == g);

  // Optional fields stay out when empty.
  const Gadget bare{"", 0, std::nullopt, Bytes{1}, false, ""};
  CHECK(detail::write_record(gadget_fields(), bare).dump() ==
        "{\"label\":\"\",\"count\":0,\"blob\":[\"01\"],\"armed\":false}");
  CHECK(*gadget_from_json("{\"count\":0,\"blob\":[\"01\"],\"armed\":false}") == bare);
}

TEST_CASE("fields: the readers' messages for a table's record", "[config][fields]") {
  CHECK(gadget_from_json("{\"count\":1,\"blob\":[],\"armed\":true,\"colour\":1}").error().message ==
        "g.json:1:44: /colour: unexpected member; expected one of: label, count, level, blob, "
        "armed, note");
  CHECK(gadget_from_json("{\"blob\":[],\"armed\":true}").error().message ==
        "g.json:1:1: /: missing member \"count\"");
  CHECK(gadget_from_json("{\"count\":1001,\"blob\":[],\"armed\":true}").error().message ==
        "g.json:1:10: /count: expected a count (0..1000), found 1001");
  CHECK(gadget_from_json("{\"count\":1,\"blob\":[],\"armed\":true,\"note\":\"x\"}", 2)
            .error()
            .message ==
        "g.json:1:42: /note: unexpected member; the note field is new in format_version 3, this "
        "file says 2");
  CHECK(
      gadget_from_xml("<g count=\"1\" armed=\"true\" colour=\"red\"><blob/></g>").error().message ==
      "g.xml: /g/@colour: unexpected attribute; expected one of: count, level, armed, note");
  CHECK(gadget_from_xml("<g count=\"1\" armed=\"true\"><blob/><x/></g>").error().message ==
        "g.xml: /g/x: unexpected element; expected one of: label, blob");
  CHECK(gadget_from_xml("<g count=\"1\" level=\"10\" armed=\"true\"><blob/></g>").error().message ==
        "g.xml: /g/@level: expected a level (0..9 in decimal), found \"10\"");
  CHECK(gadget_from_xml("<g count=\"1\" armed=\"yes\"><blob/></g>").error().message ==
        "g.xml: /g/@armed: expected true or false, found \"yes\"");
  CHECK(gadget_from_xml("<g count=\"1\" armed=\"true\"/>").error().message ==
        "g.xml: /g: missing element <blob>");
  CHECK(
      gadget_from_xml("<g count=\"1\" armed=\"true\" note=\"x\"><blob/></g>", 2).error().message ==
      "g.xml: /g/@note: unexpected attribute; the note field is new in format_version 3, this "
      "file says 2");
}

TEST_CASE("fields: validation checks every text field of a table", "[config][fields]") {
  Identity id;
  CHECK_FALSE(unclean_text(identity_fields(), id));
  id.upid_db_hash = "a\x01";
  CHECK(*unclean_text(identity_fields(), id) == "upid_db.hash");
  id.macid = "\n";
  CHECK(*unclean_text(identity_fields(), id) == "macid");
  Parameter p;
  p.scaled = "\x7F";
  CHECK(*unclean_text(parameter_fields(), p) == "scaled");
}

}  // namespace config_test_fields
