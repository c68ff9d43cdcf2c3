#pragma once
// Two writers with one interface, so that one function states a JSON
// document's members once and either builds it (JsonBuilder: an
// nlohmann::ordered_json) or writes its text directly (JsonTextWriter),
// without the objects in between. The service's list of every position is
// the reason: at thousands of positions, building and freeing the objects was
// most of an answer's time (docs/measurements.md "Plant size").
//
// Contract: for the same calls, JsonTextWriter's text is byte for byte
// `JsonBuilder::take().dump(indent, ' ', false, error_handler_t::replace)`
// (tests/config/test_json_writer.cpp). Calls must nest: a key before each
// member of an object, none in an array, every begin ended.
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace lmcfg::config {

// What both writers add to their calls (CRTP: W is the writer).
template <class W>
class JsonMembers {
 public:
  // A member of an object: its key, then its value.
  template <class T>
  void member(std::string_view k, T&& v) {
    self().key(k);
    self().value(std::forward<T>(v));
  }
  // The same, null for an empty text.
  void member_or_null(std::string_view k, const std::string& s) {
    self().key(k);
    if (s.empty())
      self().value(nullptr);
    else
      self().value(s);
  }

 private:
  W& self() { return static_cast<W&>(*this); }
};

class JsonTextWriter : public JsonMembers<JsonTextWriter> {
 public:
  // Appends to `out`; `indent` spaces a level, as dump(indent).
  explicit JsonTextWriter(std::string& out, int indent = 2) : out_(out), indent_(indent) {}

  void begin_object() { open('{'); }
  void end_object() { close('}'); }
  void begin_array() { open('['); }
  void end_array() { close(']'); }
  void key(std::string_view k);
  void value(std::string_view s);
  void value(const char* s) { value(std::string_view(s)); }
  void value(const std::string& s) { value(std::string_view(s)); }
  void value(std::int64_t v);
  void value(std::uint64_t v);
  void value(int v) { value(static_cast<std::int64_t>(v)); }
  void value(unsigned v) { value(static_cast<std::uint64_t>(v)); }
  void value(bool v);
  void value(std::nullptr_t);
  // Any value, as dump() writes it at this depth.
  void value(const nlohmann::ordered_json& j);

 private:
  void before_value();
  void separate();  // ",", newline and indent, as the open container needs
  void open(char bracket);
  void close(char bracket);
  void newline_indent(std::size_t depth);

  std::string& out_;
  int indent_;
  std::vector<bool> empty_;  // per open container: nothing in it yet
  bool after_key_ = false;
};

class JsonBuilder : public JsonMembers<JsonBuilder> {
 public:
  void begin_object() { open(nlohmann::ordered_json::object()); }
  void end_object() { stack_.pop_back(); }
  void begin_array() { open(nlohmann::ordered_json::array()); }
  void end_array() { stack_.pop_back(); }
  void key(std::string_view k) { key_ = k; }
  template <class T>
  void value(T&& v) {
    place(nlohmann::ordered_json(std::forward<T>(v)));
  }
  void value(std::string_view s) { place(nlohmann::ordered_json(std::string(s))); }
  // The document built (after the outermost end).
  nlohmann::ordered_json take() { return std::move(root_); }

 private:
  nlohmann::ordered_json* place(nlohmann::ordered_json v);
  void open(nlohmann::ordered_json v) { stack_.push_back(place(std::move(v))); }

  nlohmann::ordered_json root_;
  std::vector<nlohmann::ordered_json*> stack_;
  std::string key_;
};

}  // namespace lmcfg::config
