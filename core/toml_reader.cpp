#include "toml_reader.hpp"

#include <fmt/format.h>

namespace grainlab {

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi) return fmt::format("{}{}, {}]", lo_open ? "(" : "[", lo, hi);
  if (has_lo) return fmt::format("{} {}", lo_open ? ">" : ">=", lo);
  if (has_hi) return fmt::format("<= {}", hi);
  return "any finite number";
}

std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::table:
      return "a table";
    case toml::node_type::array:
      return "an array";
    case toml::node_type::string:
      return "a string";
    case toml::node_type::integer:
      return "an integer";
    case toml::node_type::floating_point:
      return "a number";
    case toml::node_type::boolean:
      return "a boolean";
    default:
      return "a date or time";
  }
}

SourceLocation TomlReader::where(const std::string& key) const {
  if (const toml::node* n = table_.get(key)) {
    const auto& src = n->source();
    const std::string path = src.path ? std::string(*src.path) : file_;
    // A value given on the command line (ripples::apply_overrides: "--set KEY=VALUE") has no line.
    return {path, path.rfind("--", 0) == 0 ? 0 : static_cast<int>(src.begin.line)};
  }
  return where_table();
}

SourceLocation TomlReader::where_table() const {
  const auto& src = table_.source();
  return {src.path ? std::string(*src.path) : file_, static_cast<int>(src.begin.line)};
}

void TomlReader::fail(const std::string& key, const std::string& what) const {
  throw InputError(where(key), dotted(key), what);
}

const toml::node* TomlReader::get(const std::string& key) const {
  seen_.insert(key);
  return table_.get(key);
}

const toml::node& TomlReader::need(const std::string& key) const {
  const toml::node* n = get(key);
  if (!n) throw InputError(where_table(), dotted(key), "required key is missing");
  return *n;
}

double TomlReader::checked_double(const std::string& key, const toml::node& n, Range range) const {
  if (!n.is_number()) fail(key, "expected a number, found " + type_name(n));
  const double v = n.value<double>().value();
  if (!std::isfinite(v)) fail(key, "must be finite (found " + fmt::format("{}", v) + ")");
  if (!range.contains(v)) fail(key, fmt::format("{} is out of range: must be {}", v, range.describe()));
  return v;
}

double TomlReader::number(const std::string& key, Range range) const {
  return checked_double(key, need(key), range);
}

double TomlReader::number_or(const std::string& key, double fallback, Range range) const {
  const toml::node* n = get(key);
  return n ? checked_double(key, *n, range) : fallback;
}

std::optional<double> TomlReader::optional_number(const std::string& key, Range range) const {
  const toml::node* n = get(key);
  if (!n) return std::nullopt;
  return checked_double(key, *n, range);
}

std::int64_t TomlReader::integer(const std::string& key, std::int64_t lo, std::int64_t hi) const {
  const toml::node& n = need(key);
  if (!n.is_integer()) fail(key, "expected an integer, found " + type_name(n));
  const std::int64_t v = n.value<std::int64_t>().value();
  if (v < lo || v > hi) fail(key, fmt::format("{} is out of range: must be in [{}, {}]", v, lo, hi));
  return v;
}

std::int64_t TomlReader::integer_or(const std::string& key, std::int64_t fallback, std::int64_t lo,
                                    std::int64_t hi) const {
  return table_.contains(key) ? integer(key, lo, hi) : (seen_.insert(key), fallback);
}

std::string TomlReader::string(const std::string& key) const {
  const toml::node& n = need(key);
  if (!n.is_string()) fail(key, "expected a string, found " + type_name(n));
  return std::string(*n.value<std::string_view>());
}

std::string TomlReader::string_or(const std::string& key, const std::string& fallback) const {
  return table_.contains(key) ? string(key) : (seen_.insert(key), fallback);
}

bool TomlReader::boolean_or(const std::string& key, bool fallback) const {
  const toml::node* n = get(key);
  if (!n) return fallback;
  if (!n->is_boolean()) fail(key, "expected true or false, found " + type_name(*n));
  return *n->value<bool>();
}

static std::vector<double> to_numbers(const TomlReader& r, const std::string& key, const toml::node& n,
                                      std::size_t count) {
  static const char* names[] = {"[x]", "[x, y]", "[x, y, z]", "[w, x, y, z]"};
  const std::string shape = count >= 1 && count <= 4 ? names[count - 1] : std::to_string(count) + " numbers";
  const toml::array* a = n.as_array();
  bool ok = a && a->size() == count;
  for (std::size_t i = 0; ok && i < count; ++i) ok = (*a)[i].is_number();
  if (!ok) r.fail(key, fmt::format("expected {} numbers {}, found {}", count, shape, type_name(n)));
  std::vector<double> v;
  for (std::size_t i = 0; i < count; ++i) {
    v.push_back((*a)[i].value<double>().value());
    if (!std::isfinite(v.back())) r.fail(key, "components must be finite");
  }
  return v;
}

static Vec2 to_vec2(const TomlReader& r, const std::string& key, const toml::node& n) {
  const std::vector<double> v = to_numbers(r, key, n, 2);
  return {v[0], v[1]};
}

std::vector<double> TomlReader::numbers(const std::string& key, std::size_t count) const {
  return to_numbers(*this, key, need(key), count);
}

std::vector<std::vector<double>> TomlReader::number_rows(const std::string& key, std::size_t count) const {
  const toml::node& n = need(key);
  const toml::array* a = n.as_array();
  if (!a) fail(key, fmt::format("expected an array of {}-number arrays, found {}", count, type_name(n)));
  std::vector<std::vector<double>> out;
  for (const toml::node& e : *a) out.push_back(to_numbers(*this, key, e, count));
  return out;
}

std::vector<std::vector<int>> TomlReader::index_lists(const std::string& key) const {
  const toml::node& n = need(key);
  const toml::array* a = n.as_array();
  if (!a) fail(key, "expected an array of arrays of vertex indices, found " + type_name(n));
  std::vector<std::vector<int>> out;
  for (const toml::node& e : *a) {
    const toml::array* row = e.as_array();
    if (!row) fail(key, "expected an array of vertex indices, found " + type_name(e));
    out.emplace_back();
    for (const toml::node& i : *row) {
      if (!i.is_integer()) fail(key, "vertex indices must be integers, found " + type_name(i));
      const std::int64_t v = *i.value<std::int64_t>();
      if (v < 0 || v > 1000000) fail(key, fmt::format("vertex index {} is out of range", v));
      out.back().push_back(static_cast<int>(v));
    }
  }
  return out;
}

Vec2 TomlReader::vec2(const std::string& key) const {
  return to_vec2(*this, key, need(key));
}

Vec2 TomlReader::vec2_or(const std::string& key, Vec2 fallback) const {
  const toml::node* n = get(key);
  return n ? to_vec2(*this, key, *n) : fallback;
}

std::vector<Vec2> TomlReader::vec2_list(const std::string& key) const {
  const toml::node& n = need(key);
  const toml::array* a = n.as_array();
  if (!a) fail(key, "expected an array of [x, y] pairs, found " + type_name(n));
  std::vector<Vec2> out;
  for (const toml::node& e : *a) out.push_back(to_vec2(*this, key, e));
  return out;
}

std::vector<std::string> TomlReader::string_list(const std::string& key) const {
  const toml::node& n = need(key);
  const toml::array* a = n.as_array();
  if (!a) fail(key, "expected an array of strings, found " + type_name(n));
  std::vector<std::string> out;
  for (const toml::node& e : *a) {
    if (!e.is_string()) fail(key, "expected an array of strings, found an element that is " + type_name(e));
    out.emplace_back(*e.value<std::string_view>());
  }
  return out;
}

const toml::table* TomlReader::subtable(const std::string& key) const {
  const toml::node* n = get(key);
  if (!n) return nullptr;
  if (!n->is_table()) fail(key, "expected a table, found " + type_name(*n));
  return n->as_table();
}

const toml::array* TomlReader::array_of_tables(const std::string& key) const {
  const toml::node* n = get(key);
  if (!n) return nullptr;
  const toml::array* a = n->as_array();
  if (!a || !a->is_array_of_tables())
    fail(key, "expected [[" + dotted(key) + "]] tables, found " + type_name(*n));
  return a;
}

void TomlReader::finish() const {
  for (const auto& [k, v] : table_) {
    const std::string key(k.str());
    if (!seen_.count(key))
      throw InputError(where(key), dotted(key),
                       "unknown key (see " + docs_ + " for the keys this section takes)");
  }
}

}  // namespace grainlab
