#include "config/json_writer.hpp"

namespace lmcfg::config {

namespace {

// A string as dump() writes it: printable ASCII without '"' and '\' as it
// is, anything else through nlohmann's own escaping (control characters,
// UTF-8 kept, an invalid sequence replaced by U+FFFD).
void append_string(std::string& out, std::string_view s) {
  bool plain = true;
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u > 0x7e || c == '"' || c == '\\') {
      plain = false;
      break;
    }
  }
  if (plain) {
    out += '"';
    out += s;
    out += '"';
    return;
  }
  out += nlohmann::ordered_json(std::string(s))
             .dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace

void JsonTextWriter::newline_indent(std::size_t depth) {
  out_ += '\n';
  out_.append(depth * static_cast<std::size_t>(indent_), ' ');
}

void JsonTextWriter::separate() {
  if (!empty_.back()) out_ += ',';
  empty_.back() = false;
  newline_indent(empty_.size());
}

void JsonTextWriter::before_value() {
  if (after_key_) {  // the member's key wrote the separator
    after_key_ = false;
    return;
  }
  if (!empty_.empty()) separate();  // else the document itself
}

void JsonTextWriter::key(std::string_view k) {
  separate();
  append_string(out_, k);
  out_ += ": ";
  after_key_ = true;
}

void JsonTextWriter::open(char bracket) {
  before_value();
  out_ += bracket;
  empty_.push_back(true);
}

void JsonTextWriter::close(char bracket) {
  const bool was_empty = empty_.back();
  empty_.pop_back();
  if (!was_empty) newline_indent(empty_.size());
  out_ += bracket;
}

void JsonTextWriter::value(std::string_view s) {
  before_value();
  append_string(out_, s);
}

void JsonTextWriter::value(std::int64_t v) {
  before_value();
  out_ += std::to_string(v);
}

void JsonTextWriter::value(std::uint64_t v) {
  before_value();
  out_ += std::to_string(v);
}

void JsonTextWriter::value(bool v) {
  before_value();
  out_ += v ? "true" : "false";
}

void JsonTextWriter::value(std::nullptr_t) {
  before_value();
  out_ += "null";
}

void JsonTextWriter::value(const nlohmann::ordered_json& j) {
  before_value();
  const std::string text =
      j.dump(indent_, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
  // dump() indents from column 0; a raw newline in its text is always one of
  // its own (a newline in a string is written "\n").
  const std::string pad(empty_.size() * static_cast<std::size_t>(indent_), ' ');
  for (const char c : text) {
    out_ += c;
    if (c == '\n') out_ += pad;
  }
}

nlohmann::ordered_json* JsonBuilder::place(nlohmann::ordered_json v) {
  if (stack_.empty()) {
    root_ = std::move(v);
    return &root_;
  }
  nlohmann::ordered_json& top = *stack_.back();
  if (top.is_object()) {
    nlohmann::ordered_json& slot = top[key_];
    slot = std::move(v);
    return &slot;
  }
  top.push_back(std::move(v));
  return &top.back();
}

}  // namespace lmcfg::config
