#pragma once
// Errors in what a person typed (scene files, --set overrides, command-line values).
// They carry where the mistake is so the message can name file, line and key; the CLI turns
// them into exit status 2 before anything is written.
#include <stdexcept>
#include <string>

namespace grainlab {

struct SourceLocation {
  std::string file;  // scene path, or "--set" for command-line overrides
  int line = 0;      // 1-based; 0 when unknown
};

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, std::string key, const std::string& what)
      : std::runtime_error(format(where, key, what)),
        where_(std::move(where)),
        key_(std::move(key)),
        message_(what) {}

  const SourceLocation& where() const { return where_; }
  const std::string& key() const { return key_; }
  const std::string& message() const { return message_; }  // without the location

 private:
  static std::string format(const SourceLocation& w, const std::string& key, const std::string& what) {
    std::string s = w.file;
    if (w.line > 0) s.append(":").append(std::to_string(w.line));
    if (!key.empty()) s.append(": ").append(key);
    s.append(": ").append(what);
    return s;
  }
  SourceLocation where_;
  std::string key_;
  std::string message_;
};

}  // namespace grainlab
