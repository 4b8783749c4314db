// A small streaming JSON writer for reports (evaluation results, run statistics).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace ldsm::drivers {

/// Builds pretty-printed JSON text. Inside an object call key() before each value or container.
/// Doubles are written in shortest round-trip form; NaN and infinities become null (JSON has
/// none). Misuse (a value without a key inside an object, unbalanced end*) throws ldsm::Error.
///
///   JsonWriter w;
///   w.beginObject().key("rmse").value(0.01).key("n").value(std::int64_t{3}).endObject();
///   writeFileAtomically("out.json", w.str());
class JsonWriter {
 public:
  JsonWriter& beginObject();
  JsonWriter& endObject();
  JsonWriter& beginArray();
  JsonWriter& endArray();
  JsonWriter& key(const std::string& name);
  JsonWriter& value(double v);
  JsonWriter& value(std::int64_t v);
  JsonWriter& value(std::uint64_t v);
  JsonWriter& value(int v) { return value(static_cast<std::int64_t>(v)); }
  JsonWriter& value(bool v);
  JsonWriter& value(const std::string& v);
  JsonWriter& value(const char* v) { return value(std::string(v)); }
  JsonWriter& null();
  /// An array of numbers on one line.
  JsonWriter& array(const std::vector<double>& values);

  /// The document; throws ldsm::Error while containers are still open.
  std::string str() const;

  /// JSON string literal (with quotes) of `s`.
  static std::string quote(const std::string& s);

 private:
  enum class Scope { Object, Array };
  void beforeValue();
  void newline();
  void raw(const std::string& text);

  std::string out_;
  std::vector<Scope> stack_;
  std::vector<bool> has_items_;
  bool key_pending_ = false;
  bool done_ = false;
};

}  // namespace ldsm::drivers
