// Reading and writing grainlab-splash/1 files with the HDF5 C API.
#include "splash_file.hpp"

#include <fmt/format.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "h5_handle.hpp"
#include "h5_input.hpp"
#include "input_error.hpp"
#include "interrupt.hpp"

namespace grainlab::saltation {

namespace {

namespace fs = std::filesystem;

using Handle = H5Handle;

const char* kReboundColumns = "impact,rebounded,vx,vy,spin";
const char* kEjectaColumns = "impact,vx,vy,vx_launch,vy_launch,x0,y0,type";
const char* kLateralColumns = "v_lateral,lateral0";

// ---- writing ----

void check(herr_t status, const std::string& what) {
  if (status < 0) throw std::runtime_error("writing the splash file: " + what);
}

void put_string(hid_t obj, const std::string& name, const std::string& value) {
  Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
  H5Tset_size(type.id, std::max<std::size_t>(1, value.size()));
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate2(obj, name.c_str(), type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  check(a.id, name);
  check(H5Awrite(a.id, type.id, value.empty() ? " " : value.c_str()), name);
}

void put_number(hid_t obj, const std::string& name, double value) {
  Handle space{H5Screate(H5S_SCALAR), H5Sclose};
  Handle a{H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
  check(a.id, name);
  check(H5Awrite(a.id, H5T_NATIVE_DOUBLE, &value), name);
}

// A rows x cols dataset of doubles (cols 0: a 1-D dataset of `rows`).
void put_table(hid_t parent, const std::string& name, const std::vector<double>& data, hsize_t rows,
               hsize_t cols, const std::string& columns) {
  const hsize_t dims[2] = {rows, cols};
  Handle space{H5Screate_simple(cols == 0 ? 1 : 2, dims, nullptr), H5Sclose};
  // One chunk with a Fletcher-32 checksum: a damaged byte is refused on reading, not read as data.
  Handle dcpl{H5Pcreate(H5P_DATASET_CREATE), H5Pclose};
  if (rows > 0) {
    check(H5Pset_chunk(dcpl.id, cols == 0 ? 1 : 2, dims), name);
    check(H5Pset_fletcher32(dcpl.id), name);
  }
  Handle d{H5Dcreate2(parent, name.c_str(), H5T_NATIVE_DOUBLE, space.id, H5P_DEFAULT, dcpl.id, H5P_DEFAULT),
           H5Dclose};
  check(d.id, name);
  if (!data.empty())
    check(H5Dwrite(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), name);
  if (!columns.empty()) put_string(d.id, "columns", columns);
}

template <std::size_t N>
std::vector<double> flatten(const std::vector<std::array<double, N>>& rows) {
  std::vector<double> out;
  for (const auto& r : rows) out.insert(out.end(), r.begin(), r.end());
  return out;
}

void write_cell(hid_t cells, std::size_t k, const SplashCell& c, int dimension) {
  Handle g{H5Gcreate2(cells, fmt::format("{:04d}", k).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
           H5Gclose};
  check(g.id, "cell group");
  put_number(g.id, "speed", c.speed);
  put_number(g.id, "angle", c.angle_deg);
  put_number(g.id, "impacts", static_cast<double>(c.impacts));
  put_table(g.id, "rebound", flatten(c.rebound), c.rebound.size(), 5, kReboundColumns);
  put_table(g.id, "ejecta", flatten(c.ejecta), c.ejecta.size(), 8, kEjectaColumns);
  if (dimension == 3) {
    put_table(g.id, "rebound_lateral", c.rebound_lateral, c.rebound_lateral.size(), 0, "v_lateral");
    put_table(g.id, "ejecta_lateral", flatten(c.ejecta_lateral), c.ejecta_lateral.size(), 2, kLateralColumns);
  }
  std::vector<double> m;
  std::string names;
  for (const auto& [name, v] : c.moments) {
    m.insert(m.end(), {v.mean, v.sd, v.lo, v.hi});
    names += (names.empty() ? "" : ",") + name;
  }
  put_table(g.id, "moments", m, c.moments.size(), 4, "mean,sd,lo,hi");
  Handle d{H5Dopen2(g.id, "moments", H5P_DEFAULT), H5Dclose};
  put_string(d.id, "names", names);
}

// ---- reading ----

[[noreturn]] void bad(const std::string& path, const std::string& what) {
  throw InputError({path, 0}, "splash", what);
}

std::string get_string(hid_t obj, const char* name) {
  if (H5Aexists(obj, name) <= 0) return {};
  Handle a{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  Handle type{H5Aget_type(a.id), H5Tclose};
  if (H5Tget_class(type.id) != H5T_STRING) return {};
  std::string v(H5Tget_size(type.id), '\0');
  if (H5Aread(a.id, type.id, v.data()) < 0) return {};
  return v.c_str();
}

double get_number(hid_t obj, const char* name, const std::string& path, const std::string& where) {
  if (H5Aexists(obj, name) <= 0) bad(path, fmt::format("{}: attribute \"{}\" is missing", where, name));
  Handle a{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  double v = 0;
  if (H5Aread(a.id, H5T_NATIVE_DOUBLE, &v) < 0 || !std::isfinite(v))
    bad(path, fmt::format("{}: attribute \"{}\" is not a finite number", where, name));
  return v;
}

// Reads a dataset that must have `cols` columns (0: 1-D) and finite values.
std::vector<double> get_table(hid_t parent, const std::string& name, hsize_t cols, const std::string& path,
                              const std::string& where, hsize_t& rows) {
  if (H5Lexists(parent, name.c_str(), H5P_DEFAULT) <= 0)
    bad(path, fmt::format("{}/{} is missing", where, name));
  Handle d{H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) bad(path, fmt::format("{}/{} cannot be opened", where, name));
  Handle space{H5Dget_space(d.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  hsize_t dims[2] = {0, 0};
  if (rank != (cols == 0 ? 1 : 2))
    bad(path, fmt::format("{}/{} has rank {}, expected {}", where, name, rank, cols == 0 ? 1 : 2));
  H5Sget_simple_extent_dims(space.id, dims, nullptr);
  if (cols != 0 && dims[1] != cols)
    bad(path, fmt::format("{}/{} has {} columns, expected {}", where, name, dims[1], cols));
  rows = dims[0];
  // A damaged datatype or storage record can make libhdf5 copy past the buffer (seen in the fuzz test):
  // the data must be 8-byte floats, and all of it must be stored, before anything is read.
  Handle type{H5Dget_type(d.id), H5Tclose};
  if (type.id < 0 || H5Tget_class(type.id) != H5T_FLOAT || H5Tget_size(type.id) != sizeof(double))
    bad(path, fmt::format("{}/{} does not hold 8-byte floats (damaged)", where, name));
  const hsize_t values = rows * std::max<hsize_t>(cols, 1);
  if (H5Dget_storage_size(d.id) < values * sizeof(double) && values > 0)
    bad(path, fmt::format("{}/{}: less data stored than its shape says (truncated, damaged or compressed)",
                          where, name));
  std::vector<double> out(values);
  if (!out.empty() && H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    bad(path, fmt::format("{}/{}: its data cannot be read (truncated or damaged)", where, name));
  for (double v : out)
    if (!std::isfinite(v)) bad(path, fmt::format("{}/{} holds a non-finite number", where, name));
  return out;
}

template <std::size_t N>
std::vector<std::array<double, N>> unflatten(const std::vector<double>& flat) {
  std::vector<std::array<double, N>> out(flat.size() / N);
  for (std::size_t i = 0; i < out.size(); ++i)
    std::copy_n(flat.begin() + static_cast<long>(i * N), N, out[i].begin());
  return out;
}

SplashCell read_cell(hid_t cells, const std::string& name, const std::string& path, int dimension) {
  const std::string where = "/cells/" + name;
  Handle g{H5Gopen2(cells, name.c_str(), H5P_DEFAULT), H5Gclose};
  if (g.id < 0) bad(path, where + " cannot be opened");
  SplashCell c;
  c.speed = get_number(g.id, "speed", path, where);
  c.angle_deg = get_number(g.id, "angle", path, where);
  const double impacts = get_number(g.id, "impacts", path, where);
  if (c.speed <= 0 || c.angle_deg <= 0 || c.angle_deg >= 90 || impacts < 0)
    bad(path, fmt::format("{}: speed {} and angle {} deg must be positive (angle below 90), impacts >= 0",
                          where, c.speed, c.angle_deg));
  c.impacts = static_cast<std::size_t>(impacts);
  hsize_t rows = 0;
  c.rebound = unflatten<5>(get_table(g.id, "rebound", 5, path, where, rows));
  if (!c.rebound.empty() && rows != c.impacts)
    bad(path, fmt::format("{}/rebound has {} rows but the cell records {} impacts", where, rows, c.impacts));
  c.ejecta = unflatten<8>(get_table(g.id, "ejecta", 8, path, where, rows));
  for (const EjectumRow& e : c.ejecta)
    if (e[0] < 0 || e[0] >= static_cast<double>(std::max<std::size_t>(c.impacts, 1)))
      bad(path, fmt::format("{}/ejecta names impact {}, outside 0..{}", where, e[0], c.impacts));
  if (dimension == 3) {
    // Every rebound and ejectum row has its lateral numbers, row for row.
    c.rebound_lateral = get_table(g.id, "rebound_lateral", 0, path, where, rows);
    if (rows != c.rebound.size())
      bad(path,
          fmt::format("{}/rebound_lateral has {} rows but rebound has {}", where, rows, c.rebound.size()));
    c.ejecta_lateral = unflatten<2>(get_table(g.id, "ejecta_lateral", 2, path, where, rows));
    if (rows != c.ejecta.size())
      bad(path, fmt::format("{}/ejecta_lateral has {} rows but ejecta has {}", where, rows, c.ejecta.size()));
  }
  const std::vector<double> m = get_table(g.id, "moments", 4, path, where, rows);
  Handle d{H5Dopen2(g.id, "moments", H5P_DEFAULT), H5Dclose};
  const std::string names = get_string(d.id, "names");
  std::vector<std::string> list;
  for (std::size_t at = 0; at < names.size();) {
    const std::size_t comma = std::min(names.find(',', at), names.size());
    list.push_back(names.substr(at, comma - at));
    at = comma + 1;
  }
  if (list.size() != rows)
    bad(path, fmt::format("{}/moments has {} rows but names {} moments", where, rows, list.size()));
  for (std::size_t i = 0; i < rows; ++i)
    c.moments[list[i]] = {m[4 * i], m[4 * i + 1], m[4 * i + 2], m[4 * i + 3]};
  return c;
}

herr_t collect_name(hid_t, const char* name, const H5L_info_t*, void* data) {
  static_cast<std::vector<std::string>*>(data)->push_back(name);
  return 0;
}

}  // namespace

double SplashFile::velocity_scale() const {
  return std::sqrt(gravity_cm_s2 * grain_diameter_cm);
}

const SplashCell& SplashFile::cell(std::size_t i, std::size_t j) const {
  if (i >= speeds.size() || j >= angles_deg.size()) throw std::out_of_range("splash cell outside the grid");
  return cells.at(i * angles_deg.size() + j);
}

const SplashCell& SplashFile::nearest(double speed, double angle_deg) const {
  if (cells.empty()) throw std::out_of_range("the splash file has no cells");
  // Scale each axis by its typical spacing, so a grid step counts the same on both.
  auto spacing = [&](auto get) {
    double lo = 1e300, hi = -1e300;
    for (const SplashCell& c : cells) lo = std::min(lo, get(c)), hi = std::max(hi, get(c));
    return hi > lo ? (hi - lo) / std::max<double>(1, std::sqrt(double(cells.size())) - 1) : 1.0;
  };
  const double sv = spacing([](const SplashCell& c) { return c.speed; });
  const double sa = spacing([](const SplashCell& c) { return c.angle_deg; });
  const SplashCell* best = &cells.front();
  double bd = std::numeric_limits<double>::infinity();
  for (const SplashCell& c : cells) {
    const double d = std::hypot((c.speed - speed) / sv, (c.angle_deg - angle_deg) / sa);
    if (d < bd) bd = d, best = &c;
  }
  return *best;
}

const std::vector<std::string>& splash_moment_names() {
  static const std::vector<std::string> names = {
      "rebound_probability",   "eps_ix",      "eps_iy",    "eps_i",        "theta_i",
      "ejecta_per_impact",     "ejecta_vx",   "ejecta_vy", "ejecta_speed", "ejecta_angle",
      "reptation_per_ejectum", "energy_ratio"};
  return names;
}

void write_splash_file(const std::string& path, const SplashFile& f, bool overwrite) {
  if (!overwrite && fs::exists(path)) throw std::runtime_error(path + " exists");
  const std::string tmp = fmt::format("{}.tmp-{}", path, ::getpid());
  const TempFileHold hold(tmp);  // removed if the run is stopped by a signal
  try {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    Handle file{H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
    check(file.id, "cannot create " + tmp);
    std::map<std::string, std::string> text = f.text;
    text["schema"] = kSplashSchema;
    text["layout"] = f.speeds.empty() ? "scattered" : "grid";
    for (const auto& [k, v] : text) put_string(file.id, k, v);
    put_number(file.id, "grain_diameter_cm", f.grain_diameter_cm);
    put_number(file.id, "gravity_cm_s2", f.gravity_cm_s2);
    put_number(file.id, "grain_density", f.grain_density);
    put_number(file.id, "dimension", f.dimension);
    put_number(file.id, "velocity_scale_cm_s", f.velocity_scale());
    {
      Handle grid{H5Gcreate2(file.id, "grid", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
      put_table(grid.id, "speed", f.speeds, f.speeds.size(), 0, "");
      put_table(grid.id, "angle", f.angles_deg, f.angles_deg.size(), 0, "");
    }
    Handle cells{H5Gcreate2(file.id, "cells", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose};
    for (std::size_t k = 0; k < f.cells.size(); ++k) write_cell(cells.id, k, f.cells[k], f.dimension);
  } catch (...) {
    fs::remove(tmp);
    throw;
  }
  fs::rename(tmp, path);
}

SplashFile read_splash_file(const std::string& path, bool allow_partial) {
  Handle file = open_hdf5_for_reading(path, "splash");
  SplashFile f;
  const std::string schema = get_string(file.id, "schema");
  if (schema != kSplashSchema)
    bad(path,
        fmt::format("has schema \"{}\", expected \"{}\" (not a grainlab splash file, or another version)",
                    schema, kSplashSchema));
  for (const char* k : {"schema", "layout", "kind", "title", "source", "engine", "grainlab_version", "seed",
                        "bed_preparation", "bed_scene", "created", "notes", "complete", "runs_per_cell",
                        "beds", "active_zone"})
    if (const std::string v = get_string(file.id, k); !v.empty()) f.text[k] = v;
  if (f.text["kind"] != "simulated" && f.text["kind"] != "measured")
    bad(path, fmt::format("kind \"{}\" must be \"simulated\" or \"measured\"", f.text["kind"]));
  f.grain_diameter_cm = get_number(file.id, "grain_diameter_cm", path, "/");
  f.gravity_cm_s2 = get_number(file.id, "gravity_cm_s2", path, "/");
  f.grain_density = get_number(file.id, "grain_density", path, "/");
  // Files written before 3-D splash existed carry no dimension: they are 2-D.
  if (H5Aexists(file.id, "dimension") > 0) {
    const double dim = get_number(file.id, "dimension", path, "/");
    if (dim != 2 && dim != 3) bad(path, fmt::format("dimension {} must be 2 or 3", dim));
    f.dimension = static_cast<int>(dim);
  }
  if (!(f.grain_diameter_cm > 0 && f.gravity_cm_s2 > 0))
    bad(path, "grain_diameter_cm and gravity_cm_s2 must be positive");
  if (H5Lexists(file.id, "grid", H5P_DEFAULT) <= 0) bad(path, "/grid is missing");
  Handle grid{H5Gopen2(file.id, "grid", H5P_DEFAULT), H5Gclose};
  hsize_t n = 0;
  f.speeds = get_table(grid.id, "speed", 0, path, "/grid", n);
  f.angles_deg = get_table(grid.id, "angle", 0, path, "/grid", n);
  if (H5Lexists(file.id, "cells", H5P_DEFAULT) <= 0) bad(path, "/cells is missing");
  Handle cells{H5Gopen2(file.id, "cells", H5P_DEFAULT), H5Gclose};
  std::vector<std::string> names;
  H5Literate(cells.id, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_name, &names);
  for (const std::string& name : names) f.cells.push_back(read_cell(cells.id, name, path, f.dimension));
  const bool partial = f.text.count("complete") && f.text.at("complete") == "false";
  if (partial && !allow_partial)
    bad(path,
        "is the checkpoint of an unfinished measurement (complete = false): continue it with --restart");
  if (f.cells.empty() && !partial) bad(path, "/cells holds no cell");
  if (f.text["layout"] == "grid" && !partial) {
    if (f.speeds.size() * f.angles_deg.size() != f.cells.size())
      bad(path, fmt::format("the grid is {} speeds x {} angles but the file has {} cells", f.speeds.size(),
                            f.angles_deg.size(), f.cells.size()));
    for (std::size_t i = 0; i < f.speeds.size(); ++i)
      for (std::size_t j = 0; j < f.angles_deg.size(); ++j) {
        const SplashCell& c = f.cells[i * f.angles_deg.size() + j];
        if (std::abs(c.speed - f.speeds[i]) > 1e-9 * f.speeds[i] ||
            std::abs(c.angle_deg - f.angles_deg[j]) > 1e-9)
          bad(path,
              fmt::format("cell {} sits at ({}, {}), not at grid point ({}, {})", i * f.angles_deg.size() + j,
                          c.speed, c.angle_deg, f.speeds[i], f.angles_deg[j]));
      }
  }
  return f;
}

SplashFile sand_gun_splash() {
  // Tables 3.11 and 3.12 (../shared/spec/ch3-impacts.md): per row v_i (spread), alpha_i, events,
  // eps_ix, eps_iy, theta_i with their spreads; E_out/E_in, ejecta per event, reptation per particle (cm),
  // ejecta v_y (cm/s) and ejection angle (deg).
  struct Row {
    double v, alpha, events, ix, six, iy, siy, th, sth, energy, ejecta, rep, vey, the;
  };
  static const Row rows[] = {
      {650, 15, 12, .58, .13, .80, .43, 68, 13, .42, 2.8, 4.3, 48, 34},
      {760, 16, 22, .55, .24, .71, .36, 64, 18, .40, 2.3, 4.4, 50, 27},
      {910, 16, 20, .48, .27, .72, .36, 58, 34, .36, 4.1, 4.2, 49, 23},
      {1000, 15, 18, .49, .25, .74, .30, 62, 18, .36, 5.0, 4.1, 49, 19},
      {1100, 15, 18, .54, .25, .68, .31, 64, 24, .42, 5.7, 4.7, 58, 17},
      {1200, 16, 19, .58, .17, .86, .36, 66, 13, .43, 5.7, 3.8, 54, 17},
      {880, 12, 17, .61, .17, .94, .46, 69, 13, .47, 2.9, 6.9, 60, 18},
      {1200, 10, 12, .61, .17, 1.27, .48, 67, 12, .49, 4.9, 8.7, 72, 20},
      {920, 21, 17, .50, .18, .48, .24, 66, 14, .35, 4.7, 7.9, 59, 22},
  };
  SplashFile f;
  f.grain_diameter_cm = 0.078;  // Kelso Dunes sand sieved to 0.071-0.085 cm
  f.gravity_cm_s2 = 981;
  f.grain_density = 2.65;
  f.text = {{"kind", "measured"},
            {"title", "sand-gun experiment, thesis Tables 3.11 and 3.12"},
            {"source",
             "Werner (1987) Ch. III section 6: single grains shot onto a bed of coarse sand, strobe "
             "photographs at 400 Hz (a 2-D projection); digitized from the tables, not simulated"},
            {"engine", "experiment"},
            {"notes",
             "moments only: sd is the table's spread; lo/hi are mean -+ 1.96 sd / sqrt(events) where the "
             "table gives a spread, else the mean; velocities / sqrt(g d), reptation / d; row 3's energy "
             "ratio is OCR-damaged (0.36?)"}};
  const double u = f.velocity_scale(), d = f.grain_diameter_cm;
  for (const Row& r : rows) {
    SplashCell c;
    c.speed = r.v / u, c.angle_deg = r.alpha, c.impacts = static_cast<std::size_t>(r.events);
    auto with_spread = [&](double mean, double sd) {
      const double h = 1.959963984540054 * sd / std::sqrt(r.events);
      return SplashMoment{mean, sd, mean - h, mean + h};
    };
    auto point = [](double mean) { return SplashMoment{mean, 0, mean, mean}; };
    c.moments["eps_ix"] = with_spread(r.ix, r.six);
    c.moments["eps_iy"] = with_spread(r.iy, r.siy);
    c.moments["theta_i"] = with_spread(r.th, r.sth);
    c.moments["energy_ratio"] = point(r.energy);
    c.moments["ejecta_per_impact"] = point(r.ejecta);
    c.moments["reptation_per_ejectum"] = point(r.rep / d);
    c.moments["ejecta_vy"] = point(r.vey / u);
    c.moments["ejecta_angle"] = point(r.the);
    f.cells.push_back(c);
  }
  return f;
}

std::vector<double> ejecta_hop_lengths(const SplashFile& f, double angle, double speed) {
  double best_angle = 1e300, best_speed = 1e300;
  for (const SplashCell& c : f.cells) best_angle = std::min(best_angle, std::abs(c.angle_deg - angle));
  for (const SplashCell& c : f.cells)
    if (std::abs(c.angle_deg - angle) == best_angle)
      best_speed = std::min(best_speed, std::abs(c.speed - speed));
  std::vector<double> hops;
  double reptation = 0;
  int moment_cells = 0;
  for (const SplashCell& c : f.cells) {
    if (std::abs(c.angle_deg - angle) != best_angle) continue;
    if (speed > 0 && std::abs(c.speed - speed) != best_speed) continue;
    for (const EjectumRow& e : c.ejecta)
      if (e[4] > 0) hops.push_back(2 * e[3] * e[4]);
    if (c.ejecta.empty() && c.moments.count("reptation_per_ejectum"))
      reptation += c.moments.at("reptation_per_ejectum").mean, ++moment_cells;
  }
  if (hops.empty() && moment_cells > 0)
    for (int q = 0; q < 1000; ++q) hops.push_back(-reptation / moment_cells * std::log(1 - (q + 0.5) / 1000));
  return hops;
}

}  // namespace grainlab::saltation
