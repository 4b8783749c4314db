#include "ldsm/drivers/json_writer.h"

#include <cmath>
#include <cstdio>

#include "io/number_text.h"
#include "ldsm/error.h"

namespace ldsm::drivers {

std::string JsonWriter::quote(const std::string& s) {
  std::string q = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        q += "\\\"";
        break;
      case '\\':
        q += "\\\\";
        break;
      case '\n':
        q += "\\n";
        break;
      case '\t':
        q += "\\t";
        break;
      case '\r':
        q += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", static_cast<unsigned>(c));
          q += buf;
        } else {
          q += c;
        }
    }
  }
  return q + "\"";
}

void JsonWriter::newline() {
  out_ += '\n';
  out_.append(2 * stack_.size(), ' ');
}

void JsonWriter::beforeValue() {
  if (done_) throw Error("JsonWriter: a second top-level value");
  if (stack_.empty()) return;
  if (stack_.back() == Scope::Object) {
    if (!key_pending_) throw Error("JsonWriter: value inside an object without a key");
    key_pending_ = false;
    return;
  }
  if (has_items_.back()) out_ += ',';
  has_items_.back() = true;
  newline();
}

void JsonWriter::raw(const std::string& text) {
  beforeValue();
  out_ += text;
  if (stack_.empty()) done_ = true;
}

JsonWriter& JsonWriter::key(const std::string& name) {
  if (stack_.empty() || stack_.back() != Scope::Object || key_pending_) {
    throw Error("JsonWriter: key '" + name + "' outside an object or after another key");
  }
  if (has_items_.back()) out_ += ',';
  has_items_.back() = true;
  newline();
  out_ += quote(name) + ": ";
  key_pending_ = true;
  return *this;
}

JsonWriter& JsonWriter::beginObject() {
  beforeValue();
  out_ += '{';
  stack_.push_back(Scope::Object);
  has_items_.push_back(false);
  return *this;
}

JsonWriter& JsonWriter::beginArray() {
  beforeValue();
  out_ += '[';
  stack_.push_back(Scope::Array);
  has_items_.push_back(false);
  return *this;
}

JsonWriter& JsonWriter::endObject() {
  if (stack_.empty() || stack_.back() != Scope::Object || key_pending_) {
    throw Error("JsonWriter: endObject() without a matching beginObject()");
  }
  const bool items = has_items_.back();
  stack_.pop_back();
  has_items_.pop_back();
  if (items) newline();
  out_ += '}';
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::endArray() {
  if (stack_.empty() || stack_.back() != Scope::Array) {
    throw Error("JsonWriter: endArray() without a matching beginArray()");
  }
  const bool items = has_items_.back();
  stack_.pop_back();
  has_items_.pop_back();
  if (items) newline();
  out_ += ']';
  if (stack_.empty()) done_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(double v) {
  raw(std::isfinite(v) ? number_text::formatDouble(v) : "null");
  return *this;
}

JsonWriter& JsonWriter::value(std::int64_t v) {
  raw(std::to_string(v));
  return *this;
}

JsonWriter& JsonWriter::value(std::uint64_t v) {
  raw(std::to_string(v));
  return *this;
}

JsonWriter& JsonWriter::value(bool v) {
  raw(v ? "true" : "false");
  return *this;
}

JsonWriter& JsonWriter::value(const std::string& v) {
  raw(quote(v));
  return *this;
}

JsonWriter& JsonWriter::null() {
  raw("null");
  return *this;
}

JsonWriter& JsonWriter::array(const std::vector<double>& values) {
  std::string text = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) text += ", ";
    text += std::isfinite(values[i]) ? number_text::formatDouble(values[i]) : "null";
  }
  raw(text + "]");
  return *this;
}

std::string JsonWriter::str() const {
  if (!stack_.empty())
    throw Error("JsonWriter: " + std::to_string(stack_.size()) + " containers still open");
  return out_ + "\n";
}

}  // namespace ldsm::drivers
