#pragma once
// Checked access to one TOML table: every read names file, line and dotted key on error, and
// finish() rejects keys nobody asked for (unknown keys are errors, not silently ignored).
#include <toml++/toml.h>

#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <string>

#include "input_error.hpp"
#include "vec2.hpp"

namespace grainlab {

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;  // lo itself not allowed
  static Range positive() { return {0, std::numeric_limits<double>::infinity(), true}; }
  static Range non_negative() { return {0, std::numeric_limits<double>::infinity(), false}; }
  static Range closed(double a, double b) { return {a, b, false}; }
  std::string describe() const;
  bool contains(double v) const { return (lo_open ? v > lo : v >= lo) && v <= hi; }
};

class TomlReader {
 public:
  // `docs`: the page that lists the keys this table takes, named when a key is unknown.
  TomlReader(const toml::table& table, std::string prefix, std::string file,
             std::string docs = "docs/scenes.md")
      : table_(table), prefix_(std::move(prefix)), file_(std::move(file)), docs_(std::move(docs)) {}

  bool has(const std::string& key) const { return table_.contains(key); }
  double number(const std::string& key, Range range = {}) const;
  double number_or(const std::string& key, double fallback, Range range = {}) const;
  std::optional<double> optional_number(const std::string& key, Range range = {}) const;
  std::int64_t integer(const std::string& key, std::int64_t lo, std::int64_t hi) const;
  std::int64_t integer_or(const std::string& key, std::int64_t fallback, std::int64_t lo,
                          std::int64_t hi) const;
  std::string string(const std::string& key) const;
  std::string string_or(const std::string& key, const std::string& fallback) const;
  bool boolean_or(const std::string& key, bool fallback) const;
  Vec2 vec2(const std::string& key) const;
  Vec2 vec2_or(const std::string& key, Vec2 fallback) const;
  std::vector<Vec2> vec2_list(const std::string& key) const;
  // Exactly `count` finite numbers; an array of such arrays; an array of arrays of indices.
  std::vector<double> numbers(const std::string& key, std::size_t count) const;
  std::vector<std::vector<double>> number_rows(const std::string& key, std::size_t count) const;
  std::vector<std::vector<int>> index_lists(const std::string& key) const;
  std::vector<std::string> string_list(const std::string& key) const;
  const toml::table* subtable(const std::string& key) const;
  // The raw node (marks the key as seen); nullptr when absent.
  const toml::node* node(const std::string& key) const { return get(key); }
  const toml::array* array_of_tables(const std::string& key) const;

  // Throws for the first key in the table that no accessor above was asked about.
  void finish() const;

  std::string dotted(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  SourceLocation where(const std::string& key) const;
  SourceLocation where_table() const;
  [[noreturn]] void fail(const std::string& key, const std::string& what) const;

 private:
  const toml::node* get(const std::string& key) const;
  const toml::node& need(const std::string& key) const;
  double checked_double(const std::string& key, const toml::node& n, Range range) const;

  const toml::table& table_;
  std::string prefix_;
  std::string file_;
  std::string docs_;
  mutable std::set<std::string> seen_;
};

std::string type_name(const toml::node& n);

}  // namespace grainlab
