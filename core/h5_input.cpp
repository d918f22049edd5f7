#include "h5_input.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cmath>
#include <filesystem>
#include <vector>

#include "h5_handle.hpp"
#include "input_error.hpp"

namespace grainlab {

namespace {

using Handle = H5Handle;

[[noreturn]] void corrupt(const std::string& path, const std::string& what) {
  throw InputError({path, 0}, "file", what);
}

struct Dataset {
  std::vector<hsize_t> dims;
  std::vector<double> data;
};

// Reads a whole 1-D or 2-D dataset as doubles.
Dataset read_all(hid_t parent, const std::string& name, const std::string& path) {
  Handle d{H5Dopen2(parent, name.c_str(), H5P_DEFAULT), H5Dclose};
  if (d.id < 0) corrupt(path, name + " is missing or unreadable");
  Handle space{H5Dget_space(d.id), H5Sclose};
  const int rank = H5Sget_simple_extent_ndims(space.id);
  if (rank < 1 || rank > 2) corrupt(path, name + " has an unexpected shape");
  Dataset out{std::vector<hsize_t>(static_cast<std::size_t>(rank)), {}};
  H5Sget_simple_extent_dims(space.id, out.dims.data(), nullptr);
  hsize_t count = 1;
  for (hsize_t x : out.dims) count *= x;
  // A damaged datatype or storage record can make libhdf5 copy past the buffer (seen when fuzzing splash
  // files): numbers of at most 8 bytes, all of them stored, before anything is read.
  Handle type{H5Dget_type(d.id), H5Tclose};
  const H5T_class_t kind = type.id < 0 ? H5T_NO_CLASS : H5Tget_class(type.id);
  const std::size_t size = type.id < 0 ? 0 : H5Tget_size(type.id);
  if ((kind != H5T_FLOAT && kind != H5T_INTEGER) || size == 0 || size > 8)
    corrupt(path, name + " does not hold numbers (damaged)");
  if (count > 0 && H5Dget_storage_size(d.id) < count * size)
    corrupt(path,
            name + ": less data stored than its shape says (the file is truncated, damaged or compressed)");
  out.data.resize(count);
  if (count > 0 && H5Dread(d.id, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data.data()) < 0)
    corrupt(path, name + ": its data cannot be read (the file is truncated or damaged)");
  return out;
}

struct AttributeSink {
  RunFileSummary* summary;
  bool numbers;  // also keep numeric attributes (as diagnostics)
};

herr_t take_attribute(hid_t obj, const char* name, const H5A_info_t*, void* data) {
  auto* sink = static_cast<AttributeSink*>(data);
  Handle a{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  if (a.id < 0) return 0;
  Handle type{H5Aget_type(a.id), H5Tclose};
  if (H5Tget_class(type.id) == H5T_STRING) {
    std::string v(H5Tget_size(type.id), '\0');
    if (H5Aread(a.id, type.id, v.data()) >= 0) sink->summary->text[name] = v.c_str();
  } else if (sink->numbers) {
    double v = 0;
    if (H5Aread(a.id, H5T_NATIVE_DOUBLE, &v) >= 0) sink->summary->diagnostics[name] = v;
  }
  return 0;
}

void read_attributes(hid_t obj, RunFileSummary& s, bool numbers) {
  AttributeSink sink{&s, numbers};
  H5Aiterate2(obj, H5_INDEX_NAME, H5_ITER_INC, nullptr, take_attribute, &sink);
}

Handle open_checked(const std::string& path) {
  return open_hdf5_for_reading(path, "file");
}

std::string string_attribute(hid_t obj, const char* name) {
  Handle a{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  if (a.id < 0) return {};
  Handle type{H5Aget_type(a.id), H5Tclose};
  if (H5Tget_class(type.id) != H5T_STRING) return {};
  std::string v(H5Tget_size(type.id), '\0');
  if (H5Aread(a.id, type.id, v.data()) < 0) return {};
  return v.c_str();
}

}  // namespace

H5Handle open_hdf5_for_reading(const std::string& path, const std::string& key) {
  if (!std::filesystem::exists(path)) throw InputError({path, 0}, key, "does not exist");
  if (std::filesystem::is_directory(path)) throw InputError({path, 0}, key, "is a folder, not a file");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw InputError({path, 0}, key, "is not an HDF5 file (or its header is damaged)");
  H5Handle f{H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
  if (f.id < 0) throw InputError({path, 0}, key, "cannot be opened as HDF5: it is truncated or damaged");
  return f;
}

namespace {

double double_attribute(hid_t obj, const char* name, const std::string& path, const std::string& where) {
  Handle a{H5Aopen(obj, name, H5P_DEFAULT), H5Aclose};
  double v = 0;
  if (a.id < 0 || H5Aread(a.id, H5T_NATIVE_DOUBLE, &v) < 0)
    corrupt(path, fmt::format("{} has no readable {} attribute", where, name));
  return v;
}

// One frame group, its columns checked against its positions.
Frame read_frame(hid_t file, const std::string& g, const std::string& path) {
  Handle group{H5Gopen2(file, g.c_str(), H5P_DEFAULT), H5Gclose};
  if (group.id < 0) corrupt(path, g + " is missing");
  Frame f;
  f.time = double_attribute(group.id, "time", path, g);
  const Dataset position = read_all(group.id, "position", path);
  const hsize_t n = position.dims[0];
  auto column = [&](const char* name, hsize_t width) {
    Dataset d = read_all(group.id, name, path);
    if (d.dims[0] != n || (d.dims.size() == 2 ? d.dims[1] : 1) != width)
      corrupt(path, fmt::format("{}/{} does not fit its {} bodies", g, name, n));
    return std::move(d.data);
  };
  auto whole = [](const std::vector<double>& v, auto type) {
    return std::vector<decltype(type)>(v.begin(), v.end());
  };
  if (position.dims.size() != 2 || position.dims[1] != 3) corrupt(path, g + "/position is not N x 3");
  f.position = position.data;
  f.id = whole(column("id", 1), std::int64_t{});
  f.velocity = column("velocity", 3);
  f.orientation = column("orientation", 4);
  f.angular_velocity = column("angular_velocity", 3);
  f.radius = column("radius", 1);
  f.shape = whole(column("shape", 1), std::int32_t{});
  if (H5Lexists(group.id, "angle", H5P_DEFAULT) > 0) {
    f.angle = column("angle", 1);
    f.spin = column("spin", 1);
  }
  return f;
}

}  // namespace

RunFileSummary read_run_file(const std::string& path) {
  Handle f = open_checked(path);
  RunFileSummary s;
  read_attributes(f.id, s, false);
  if (!s.text.count("grainlab_version"))
    corrupt(path, "is not a grainlab run file (no grainlab_version attribute)");
  Handle frames{H5Gopen2(f.id, "/frames", H5P_DEFAULT), H5Gclose};
  if (frames.id < 0) corrupt(path, "has no /frames group");
  const Dataset times = read_all(frames.id, "time", path);
  s.frames = times.dims[0];
  if (s.frames > 0) s.first_time = times.data.front(), s.last_time = times.data.back();
  for (std::size_t k = 0; k < s.frames; ++k) {
    const Frame frame = read_frame(f.id, fmt::format("/frames/{:06d}", k), path);
    if (k == 0) s.bodies = frame.id.size();
  }
  Handle energy{H5Gopen2(f.id, "/energy", H5P_DEFAULT), H5Gclose};
  if (energy.id < 0) corrupt(path, "has no /energy group");
  Handle diagnostics{H5Gopen2(f.id, "/diagnostics", H5P_DEFAULT), H5Gclose};
  if (diagnostics.id < 0) corrupt(path, "has no /diagnostics group");
  read_attributes(diagnostics.id, s, true);
  return s;
}

void read_frames(const std::string& path, const std::string& group, std::size_t count,
                 const std::function<void(const Frame&)>& take) {
  Handle f = open_checked(path);
  for (std::size_t k = 0; k < count; ++k) take(read_frame(f.id, fmt::format("{}/{:06d}", group, k), path));
}

TableFile read_sample_tables(const std::string& path,
                             const std::map<std::string, std::vector<std::string>>& wanted) {
  Handle f = open_checked(path);
  TableFile out;
  RunFileSummary attributes;
  read_attributes(f.id, attributes, false);
  out.metadata = attributes.text;
  for (const auto& [name, columns] : wanted) {
    const Dataset d = read_all(f.id, name, path);
    Handle ds{H5Dopen2(f.id, name.c_str(), H5P_DEFAULT), H5Dclose};
    const std::string found = string_attribute(ds.id, "columns");
    // No wanted columns: take the table's own (one name per column, all present).
    std::vector<std::string> names = columns;
    if (names.empty())
      for (std::size_t a = 0; a <= found.size();) {
        const std::size_t b = std::min(found.find(',', a), found.size());
        names.push_back(found.substr(a, b - a));
        a = b + 1;
      }
    const std::string expected = fmt::format("{}", fmt::join(names, ","));
    if (found != expected || d.dims.size() != 2 || d.dims[1] != names.size())
      corrupt(path, fmt::format("table {} has columns \"{}\", expected \"{}\"", name, found, expected));
    SampleTable t{name, string_attribute(ds.id, "description"), names, {}};
    for (hsize_t r = 0; r < d.dims[0]; ++r)
      t.rows.emplace_back(d.data.begin() + static_cast<long>(r * d.dims[1]),
                          d.data.begin() + static_cast<long>((r + 1) * d.dims[1]));
    out.tables[name] = std::move(t);
  }
  return out;
}

std::map<std::string, H5Object> root_objects(const std::string& path) {
  return group_objects(path, "/");
}

std::map<std::string, H5Object> group_objects(const std::string& path, const std::string& group) {
  Handle f = open_checked(path);
  Handle g{H5Gopen2(f.id, group.c_str(), H5P_DEFAULT), H5Gclose};
  if (g.id < 0) corrupt(path, group + " is missing or not a group");
  std::map<std::string, H5Object> out;
  // (HDF5 1.10's calls, as Debian 12 ships it.)
  auto visit = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    H5O_info_t info;
    if (H5Oget_info_by_name2(group, name, &info, H5O_INFO_BASIC, H5P_DEFAULT) < 0) return -1;
    const bool dataset = info.type == H5O_TYPE_DATASET;
    if (!dataset && info.type != H5O_TYPE_GROUP) return 0;
    H5Object o{dataset, dataset && H5Aexists_by_name(group, name, "columns", H5P_DEFAULT) > 0, 0};
    if (H5G_info_t g; !dataset && H5Gget_info_by_name(group, name, &g, H5P_DEFAULT) >= 0)
      o.members = g.nlinks;
    (*static_cast<std::map<std::string, H5Object>*>(data))[name] = o;
    return 0;
  };
  if (H5Literate(g.id, H5_INDEX_NAME, H5_ITER_INC, nullptr, visit, &out) < 0)
    corrupt(path, group == "/" ? "its top-level objects cannot be listed"
                               : "the objects of " + group + " cannot be listed");
  return out;
}

GridFrame read_grid_frame(const std::string& path, std::size_t k) {
  Handle f = open_checked(path);
  const std::string name = fmt::format("/frames/{:06d}", k);
  const Dataset d = read_all(f.id, name, path);
  if (d.dims.size() != 2) corrupt(path, name + " is not a 2-D field");
  GridFrame g;
  g.ny = d.dims[0], g.nx = d.dims[1];
  for (double v : d.data)
    if (!std::isfinite(v)) corrupt(path, name + " holds a value that is not a finite number");
  g.values = d.data;
  Handle ds{H5Dopen2(f.id, name.c_str(), H5P_DEFAULT), H5Dclose};
  g.time = double_attribute(ds.id, "time", path, name);
  return g;
}

void require_checkpoint(const TableFile& file, const std::string& path, const std::string& kind,
                        const std::string& what, const std::string& options, const std::string& mismatch) {
  auto refuse = [&](const std::string& why) { throw InputError({path, 0}, "--restart", why); };
  auto meta = [&](const char* key) {
    auto it = file.metadata.find(key);
    return it == file.metadata.end() ? std::string() : it->second;
  };
  if (meta("kind") != kind) refuse(fmt::format("is not a {} (kind \"{}\")", what, meta("kind")));
  if (meta("grainlab_version") != GRAINLAB_VERSION)
    refuse(fmt::format("was written by grainlab {}, this is {}", meta("grainlab_version"), GRAINLAB_VERSION));
  if (meta("options") != options) refuse(mismatch);
}

}  // namespace grainlab
