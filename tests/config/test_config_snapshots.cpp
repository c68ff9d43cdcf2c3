// What the readers and writers did before they walked the field table, kept as
// snapshots: every fixture written in both formats (byte for byte), and the
// message of every reader for thousands of mutated documents (a member or
// attribute removed, given another type or value, an unknown one added).
// LMCFG_UPDATE_GOLDEN=1 rewrites the snapshots; a change to them is a change
// of behaviour and needs a reason.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>
#include <sstream>

#include "config/config_io.hpp"
#include "config/json_io.hpp"
#include "config/xml_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_config_snapshots {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;
namespace fs = std::filesystem;

namespace {

struct NamingCtDecoder : CtEntryDecoder {
  std::optional<CtEntryView> decode(std::uint32_t id, ByteView raw) const override {
    if (id % 2 != 0) return std::nullopt;
    return CtEntryView{"Entry " + std::to_string(id) + " \"" + ct_entry_name(raw) + "\"",
                       {{"Position", "100", "mm"}, {"Flag", "x", ""}}};
  }
};

fs::path snapshot_dir() { return fixture_dir() / "snapshots"; }

void check_snapshot(const fs::path& path, const std::string& text) {
  if (std::getenv("LMCFG_UPDATE_GOLDEN")) spit(path, text);
  INFO(path.string());
  const std::string stored = slurp(path);
  REQUIRE_FALSE(stored.empty());
  CHECK(stored == text);
}

std::vector<fs::path> fixtures() {
  std::vector<fs::path> out;
  for (const auto& ent : fs::directory_iterator(fixture_dir())) {
    const auto ext = ent.path().extension();
    if (ent.is_regular_file() && (ext == ".json" || ext == ".xml")) out.push_back(ent.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

// FNV-1a of a written file: a read that succeeds is recorded by what it read.
std::string digest(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  std::ostringstream o;
  o << std::hex << h;
  return o.str();
}

std::string outcome(const Result<DriveConfig>& r) {
  if (!r.ok()) return std::to_string(r.error().code.value()) + " " + r.error().message;
  auto w = write_json(*r);
  return "ok " + (w.ok() ? digest(*w) : "unwritable: " + w.error().message);
}

using ojson = nlohmann::ordered_json;

void json_pointers(const ojson& j, const std::string& at, std::vector<std::string>& out) {
  out.push_back(at);
  if (at.size() > 8 && at.substr(at.size() - 8) == "/decoded") return;  // derived: not read
  if (j.is_object())
    for (auto it = j.begin(); it != j.end(); ++it)
      json_pointers(it.value(), at + "/" + it.key(), out);
  if (j.is_array())
    for (std::size_t i = 0; i < j.size(); ++i)
      json_pointers(j[i], at + "/" + std::to_string(i), out);
}

std::string json_messages(const fs::path& file) {
  const ojson doc = ojson::parse(slurp(file));
  std::vector<std::string> ptrs;
  json_pointers(doc, "", ptrs);
  const ojson replacements[] = {"x",    7,       -1,      4294967296ull,   65536,
                                16,     true,    nullptr, ojson::object(), ojson::array(),
                                "13A2", "01 02", "A"};
  std::string log;
  const auto record = [&](const std::string& what, const ojson& d) {
    log += what + " => " + outcome(read_json(d.dump(2), "m.json")) + "\n";
  };
  for (const auto& p : ptrs) {
    if (p.empty()) continue;
    const ojson::json_pointer jp(p);
    {
      ojson d = doc;
      d[jp.parent_pointer()].is_object()
          ? (void)d[jp.parent_pointer()].erase(jp.back())
          : (void)d[jp.parent_pointer()].erase(std::stoul(jp.back()));
      record(p + " removed", d);
    }
    for (const auto& r : replacements) {
      ojson d = doc;
      d[jp] = r;
      record(p + " = " + r.dump(), d);
    }
    if (doc[jp].is_object()) {
      ojson d = doc;
      d[jp]["zz"] = 1;
      record(p + " + zz", d);
    }
  }
  return log;
}

std::string xml_text(const pugi::xml_document& d) {
  std::ostringstream o;
  d.save(o, "  ", pugi::format_indent, pugi::encoding_utf8);
  return o.str();
}

// Element i (document order) of a copy of the document.
pugi::xml_node nth_element(pugi::xml_document& d, std::size_t i) {
  std::size_t k = 0;
  pugi::xml_node found;
  struct Walker : pugi::xml_tree_walker {
    std::size_t want, *k;
    pugi::xml_node* found;
    bool for_each(pugi::xml_node& n) override {
      if (n.type() != pugi::node_element) return true;
      if ((*k)++ == want) {
        *found = n;
        return false;
      }
      return true;
    }
  } w;
  w.want = i;
  w.k = &k;
  w.found = &found;
  d.traverse(w);
  return found;
}

std::string xml_messages(const fs::path& file) {
  const std::string text = slurp(file);
  std::string log;
  const auto load = [&](pugi::xml_document& d) {
    REQUIRE(d.load_string(text.c_str(), pugi::parse_default | pugi::parse_declaration));
  };
  const auto record = [&](const std::string& what, const pugi::xml_document& d) {
    log += what + " => " + outcome(read_xml(xml_text(d), "m.xml")) + "\n";
  };
  for (std::size_t i = 0;; ++i) {
    pugi::xml_document d0;
    load(d0);
    pugi::xml_node n0 = nth_element(d0, i);
    if (!n0) break;
    const std::string at = std::string(n0.path());
    if (at.find("/decoded/") != std::string::npos) continue;
    const std::string label = at + "#" + std::to_string(i);
    {
      pugi::xml_document d;
      load(d);
      pugi::xml_node n = nth_element(d, i);
      n.parent().remove_child(n);
      record(label + " removed", d);
    }
    {
      pugi::xml_document d;
      load(d);
      nth_element(d, i).append_attribute("zz") = "1";
      record(label + " + @zz", d);
    }
    {
      pugi::xml_document d;
      load(d);
      nth_element(d, i).append_child("zz");
      record(label + " + <zz>", d);
    }
    {
      pugi::xml_document d;
      load(d);
      nth_element(d, i).append_child(pugi::node_pcdata).set_value("t");
      record(label + " + text", d);
    }
    {
      pugi::xml_document d;
      load(d);
      pugi::xml_node n = nth_element(d, i);
      n.parent().insert_copy_after(n, n);
      record(label + " twice", d);
    }
    std::vector<std::string> attrs;
    for (auto a : n0.attributes()) attrs.push_back(a.name());
    for (const auto& a : attrs) {
      {
        pugi::xml_document d;
        load(d);
        nth_element(d, i).remove_attribute(a.c_str());
        record(label + "/@" + a + " removed", d);
      }
      for (const char* v : {"x", "-1", "", "4294967296", "65536", "16", "true", "13A2", "01 02",
                            "A", "1 1", "B A"}) {
        pugi::xml_document d;
        load(d);
        nth_element(d, i).attribute(a.c_str()).set_value(v);
        record(label + "/@" + a + " = \"" + v + "\"", d);
      }
    }
  }
  return log;
}

}  // namespace

TEST_CASE("config: every fixture written in both formats matches its snapshot",
          "[config][snapshots]") {
  NamingCtDecoder dec;
  WriteOptions decoded;
  decoded.ct_decoder = &dec;
  WriteOptions bare;
  bare.include_decoded = false;
  const auto all = fixtures();
  CHECK(all.size() >= 8);
  for (const auto& f : all) {
    const auto cfg = must(read_config_file(f));
    const std::string stem = f.filename().string();
    check_snapshot(snapshot_dir() / (stem + ".written.json"), must(write_json(cfg, decoded)));
    check_snapshot(snapshot_dir() / (stem + ".written.xml"), must(write_xml(cfg, decoded)));
    check_snapshot(snapshot_dir() / (stem + ".bare.json"), must(write_json(cfg, bare)));
    check_snapshot(snapshot_dir() / (stem + ".bare.xml"), must(write_xml(cfg, bare)));
  }
}

TEST_CASE("config: the readers' messages for mutated fixtures match their snapshot",
          "[config][snapshots]") {
  for (const auto& f : fixtures()) {
    const std::string stem = f.filename().string();
    INFO(stem);
    const std::string log = f.extension() == ".json" ? json_messages(f) : xml_messages(f);
    CHECK(std::count(log.begin(), log.end(), '\n') > 100);
    check_snapshot(snapshot_dir() / (stem + ".messages.txt"), log);
  }
}

}  // namespace config_test_config_snapshots
