#include "h5_output.hpp"

#include <fmt/format.h>
#include <hdf5.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace grainlab {

namespace fs = std::filesystem;

namespace {

// Every file grainlab writes uses the HDF5 1.10 format: a dataset held in one chunk needs no chunk index,
// so checksummed small datasets cost little more than plain ones, and attributes beyond 64 kB (the text
// of a scene with thousands of bodies) are stored densely instead of failing. Readable by HDF5 1.10 and
// later (ParaView, h5py).
hid_t create_file(const std::string& path) {
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_libver_bounds(fapl, H5F_LIBVER_V110, H5F_LIBVER_V110);
  const hid_t f = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  H5Pclose(fapl);
  return f;
}

std::string temp_name(const std::string& path) {
  return fmt::format("{}.tmp-{}", path, ::getpid());
}

void check(herr_t status, const char* what) {
  if (status < 0) throw std::runtime_error(std::string("HDF5: failed to ") + what);
}

void attr_string(hid_t obj, const std::string& name, const std::string& value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, std::max<size_t>(1, value.size()));
  H5Tset_cset(type, H5T_CSET_UTF8);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(a, type, value.data()), "write a string attribute");
  H5Aclose(a), H5Sclose(space), H5Tclose(type);
}

void attr_double(hid_t obj, const std::string& name, double v) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(obj, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT);
  check(H5Awrite(a, H5T_NATIVE_DOUBLE, &v), "write an attribute");
  H5Aclose(a), H5Sclose(space);
}

template <typename T>
hid_t native_type() {
  if constexpr (std::is_same_v<T, double>)
    return H5T_NATIVE_DOUBLE;
  else if constexpr (std::is_same_v<T, std::int64_t>)
    return H5T_NATIVE_INT64;
  else
    return H5T_NATIVE_INT32;
}

template <typename T>
void dataset(hid_t parent, const std::string& name, const std::vector<T>& data, hsize_t rows,
             hsize_t cols = 1) {
  hsize_t dims[2] = {rows, cols};
  hid_t space = H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr);
  // Fletcher-32 checksums (one chunk per dataset) let a reader detect damaged data, not only a cut file.
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  if (rows * cols > 0) {
    H5Pset_chunk(dcpl, cols == 1 ? 1 : 2, dims);
    H5Pset_fletcher32(dcpl);
  }
  hid_t d = H5Dcreate2(parent, name.c_str(), native_type<T>(), space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Pclose(dcpl);
  if (d < 0) throw std::runtime_error("HDF5: failed to create dataset " + name);
  if (rows * cols > 0)
    check(H5Dwrite(d, native_type<T>(), H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), "write data");
  H5Dclose(d), H5Sclose(space);
}

std::string frame_group(std::size_t k) {
  return fmt::format("/frames/{:06d}", k);
}

}  // namespace

RunWriter::RunWriter(std::string path, bool overwrite) : path_(std::move(path)), tmp_(temp_name(path_)) {
  if (!overwrite && fs::exists(path_))
    throw std::runtime_error(fmt::format("{} exists; pass --force to overwrite it", path_));
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  file_ = create_file(tmp_);
  if (file_ < 0) throw std::runtime_error("cannot create " + tmp_);
  H5Gclose(H5Gcreate2(file_, "/frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT));
}

RunWriter::~RunWriter() {
  if (file_ >= 0) H5Fclose(file_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void RunWriter::add_frame(const Frame& fr) {
  const hsize_t n = fr.id.size();
  hid_t g = H5Gcreate2(file_, frame_group(index_.size()).c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  if (g < 0) throw std::runtime_error("HDF5: failed to create " + frame_group(index_.size()));
  attr_double(g, "time", fr.time);
  dataset(g, "id", fr.id, n);
  dataset(g, "position", fr.position, n, 3);
  dataset(g, "velocity", fr.velocity, n, 3);
  if (!fr.angle.empty()) dataset(g, "angle", fr.angle, n);
  if (!fr.spin.empty()) dataset(g, "spin", fr.spin, n);
  dataset(g, "orientation", fr.orientation, n, 4);
  dataset(g, "angular_velocity", fr.angular_velocity, n, 3);
  dataset(g, "radius", fr.radius, n);
  dataset(g, "shape", fr.shape, n);
  H5Gclose(g);
  // Flushed, so the data leaves memory now and a reader of the temporary file sees whole frames.
  check(H5Fflush(file_, H5F_SCOPE_LOCAL), "flush a frame");
  index_.push_back({fr.time, static_cast<std::size_t>(n), !fr.angle.empty()});
}

void RunWriter::copy_frames(std::int64_t dest, const std::string& group) {
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  hid_t g = H5Gcreate2(dest, group.c_str(), lcpl, H5P_DEFAULT, H5P_DEFAULT);
  H5Pclose(lcpl);
  if (g < 0) throw std::runtime_error("HDF5: failed to create " + group);
  H5Gclose(g);
  for (std::size_t k = 0; k < index_.size(); ++k)
    check(H5Ocopy(file_, frame_group(k).c_str(), dest, fmt::format("{}/{:06d}", group, k).c_str(),
                  H5P_DEFAULT, H5P_DEFAULT),
          "copy a frame");
}

void RunWriter::finish_h5() {
  hid_t f = file_;
  for (const auto& [k, v] : meta_.text) attr_string(f, k, v);
  for (const auto& [k, v] : meta_.numbers) attr_double(f, k, v);
  std::vector<double> times;
  for (const WrittenFrame& w : index_) times.push_back(w.time);
  hid_t frames = H5Gopen2(f, "/frames", H5P_DEFAULT);
  dataset(frames, "time", times, times.size());
  H5Gclose(frames);

  hid_t en = H5Gcreate2(f, "/energy", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  for (std::size_t c = 0; c < energy_columns_.size(); ++c) {
    std::vector<double> col;
    for (const auto& row : energy_) col.push_back(row[c]);
    dataset(en, energy_columns_[c], col, col.size());
  }
  H5Gclose(en);

  hid_t sh = H5Gcreate2(f, "/shapes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  for (std::size_t k = 0; k < polygons_.size(); ++k)
    dataset(sh, fmt::format("{}_{}", shape_columns_ == 2 ? "polygon" : "polyhedron", k), polygons_[k],
            polygons_[k].size() / shape_columns_, shape_columns_);
  H5Gclose(sh);

  if (contacts_) {
    const ContactEventTable& c = *contacts_;
    const hsize_t n = c.body_a.size();
    hid_t ce = H5Gcreate2(f, "/contact_events", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    attr_string(
        ce, "description",
        "one row per contact event; body_b = -1 - k for wall k; normal_impulse is the integral of the "
        "normal force over the contact, peak_force the largest step-mean normal force (scene units)");
    dataset(ce, "body_a", c.body_a, n);
    dataset(ce, "body_b", c.body_b, n);
    dataset(ce, "t_begin", c.t_begin, n);
    dataset(ce, "t_end", c.t_end, n);
    dataset(ce, "normal_impulse", c.normal_impulse, n);
    dataset(ce, "peak_force", c.peak_force, n);
    dataset(ce, "open", c.open, n);
    H5Gclose(ce);
  }

  hid_t dg = H5Gcreate2(f, "/diagnostics", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  for (const auto& [k, v] : diagnostics_) attr_double(dg, k, v);
  H5Gclose(dg);
  file_ = -1;
  check(H5Fclose(f), "close the file");
}

void RunWriter::write_xdmf(const std::string& tmp) const {
  const std::string h5 = fs::path(path_).filename().string();
  std::string x =
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
      "  <Grid Name=\"particles\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < index_.size(); ++k) {
    const std::size_t n = index_[k].bodies;
    const std::string g = frame_group(k);
    auto item = [&](const std::string& name, const char* type, int prec, const std::string& dims) {
      return fmt::format(
          "     <DataItem Dimensions=\"{}\" NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:{}/{}"
          "</DataItem>\n",
          dims, type, prec, h5, g, name);
    };
    x += fmt::format("   <Grid Name=\"frame{}\" GridType=\"Uniform\">\n    <Time Value=\"{:.17g}\"/>\n", k,
                     index_[k].time);
    x += fmt::format(
        "    <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" NodesPerElement=\"1\"/>\n", n);
    x += "    <Geometry GeometryType=\"XYZ\">\n" + item("position", "Float", 8, fmt::format("{} 3", n)) +
         "    </Geometry>\n";
    auto attribute = [&](const std::string& name, const char* kind, const char* type,
                         const std::string& dims) {
      x += fmt::format("    <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Node\">\n", name, kind) +
           item(name, type, 8, dims) + "    </Attribute>\n";
    };
    const std::string vec = fmt::format("{} 3", n), scalar = std::to_string(n);
    attribute("velocity", "Vector", "Float", vec);
    attribute("angular_velocity", "Vector", "Float", vec);
    if (index_[k].planar) {  // 2-D only
      attribute("angle", "Scalar", "Float", scalar);
      attribute("spin", "Scalar", "Float", scalar);
    }
    attribute("radius", "Scalar", "Float", scalar);
    attribute("id", "Scalar", "Int", scalar);
    x += "   </Grid>\n";
  }
  x += "  </Grid>\n </Domain>\n</Xdmf>\n";
  std::ofstream out(tmp);
  out << x;
  if (!out) throw std::runtime_error("cannot write " + tmp);
}

std::string RunWriter::commit() {
  const std::string xmf = fs::path(path_).replace_extension(".xmf").string(), tmp_xmf = temp_name(xmf);
  const TempFileHold xmf_hold(tmp_xmf);
  try {
    finish_h5();
    write_xdmf(tmp_xmf);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp_xmf, ec);
    throw;  // (the destructor removes the temporary .h5)
  }
  fs::rename(tmp_, path_);
  fs::rename(tmp_xmf, xmf);
  committed_ = true;
  hold_.release();
  return xmf;
}

namespace {

// One table as a checksummed 2-D dataset (a damaged table is refused on reading, as run files are), its
// intermediate groups ("suite/engine") created as needed.
void write_table(hid_t f, const SampleTable& t) {
  std::vector<double> flat;
  for (const auto& row : t.rows) {
    if (row.size() != t.columns.size())
      throw std::logic_error("sample table " + t.name + ": row width differs from its columns");
    flat.insert(flat.end(), row.begin(), row.end());
  }
  hsize_t dims[2] = {t.rows.size(), t.columns.size()};
  hid_t space = H5Screate_simple(2, dims, nullptr);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE), lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  if (!flat.empty()) H5Pset_chunk(dcpl, 2, dims), H5Pset_fletcher32(dcpl);
  hid_t d = H5Dcreate2(f, t.name.c_str(), H5T_NATIVE_DOUBLE, space, lcpl, dcpl, H5P_DEFAULT);
  H5Pclose(dcpl), H5Pclose(lcpl);
  if (d < 0) throw std::runtime_error("HDF5: failed to create dataset " + t.name);
  if (!flat.empty())
    check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, flat.data()), "write samples");
  attr_string(d, "columns", fmt::format("{}", fmt::join(t.columns, ",")));
  attr_string(d, "description", t.description);
  H5Dclose(d), H5Sclose(space);
}

}  // namespace

void write_sample_tables(const std::string& path, const std::vector<SampleTable>& tables,
                         const std::map<std::string, std::string>& metadata,
                         const std::function<void(std::int64_t)>& extra) {
  const std::string tmp = temp_name(path);
  const TempFileHold hold(tmp);
  hid_t f = -1;
  try {
    f = create_file(tmp);
    if (f < 0) throw std::runtime_error("cannot create " + path);
    for (const auto& [k, v] : metadata) attr_string(f, k, v);
    for (const SampleTable& t : tables) write_table(f, t);
    if (extra) extra(f);
    const hid_t closing = f;
    f = -1;
    check(H5Fclose(closing), "close the samples file");
  } catch (...) {
    if (f >= 0) H5Fclose(f);
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, path);
}

void write_file_atomically(const std::string& path, const std::string& text) {
  const std::string tmp = temp_name(path);
  const TempFileHold hold(tmp);
  {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    if (!out) {
      std::error_code ec;
      fs::remove(tmp, ec);
      throw std::runtime_error("cannot write " + path);
    }
  }
  fs::rename(tmp, path);
}

GridSeriesWriter::GridSeriesWriter(std::string path, bool overwrite, std::size_t nx, std::size_t ny,
                                   double dx, std::string field)
    : path_(std::move(path)), tmp_(temp_name(path_)), field_(std::move(field)), nx_(nx), ny_(ny), dx_(dx) {
  if (!overwrite && fs::exists(path_)) throw std::runtime_error(path_ + " exists");
  file_ = create_file(tmp_);
  if (file_ < 0) throw std::runtime_error("cannot create " + path_);
  hid_t g = H5Gcreate2(file_, "/frames", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Gclose(g);
}

GridSeriesWriter::~GridSeriesWriter() {
  if (file_ >= 0) H5Fclose(file_);
  if (!committed_) {
    std::error_code ec;
    fs::remove(tmp_, ec);
  }
}

void GridSeriesWriter::add_frame(double time, const std::vector<double>& values) {
  if (values.size() != nx_ * ny_) throw std::logic_error("grid frame: wrong number of values");
  const std::string name = fmt::format("/frames/{:06d}", times_.size());
  hsize_t dims[2] = {ny_, nx_};
  hid_t space = H5Screate_simple(2, dims, nullptr);
  hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(dcpl, 2, dims), H5Pset_fletcher32(dcpl);
  hid_t d = H5Dcreate2(file_, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
  H5Pclose(dcpl);
  if (d < 0) throw std::runtime_error("HDF5: failed to create " + name);
  check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data()), "write a frame");
  attr_double(d, "time", time);
  H5Dclose(d), H5Sclose(space);
  H5Fflush(file_, H5F_SCOPE_LOCAL);
  times_.push_back(time);
}

std::string GridSeriesWriter::commit(const std::vector<SampleTable>& tables,
                                     const std::map<std::string, std::string>& metadata) {
  const std::string xmf = fs::path(path_).replace_extension(".xmf").string(), tmp_xmf = temp_name(xmf);
  const TempFileHold xmf_hold(tmp_xmf);
  try {
    for (const SampleTable& t : tables) write_table(file_, t);
    for (const auto& [k, v] : metadata) attr_string(file_, k, v);
    check(H5Fclose(file_), "close the grid series");
    file_ = -1;
    write_file_atomically(tmp_xmf, xdmf());
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp_xmf, ec);
    throw;
  }
  fs::rename(tmp_, path_);
  fs::rename(tmp_xmf, xmf);
  committed_ = true;
  hold_.release();
  return xmf;
}

// A temporal collection of 2-D co-rectilinear grids, one per frame, each with its values as a node scalar
// (ParaView: colour by the field, or Warp By Scalar for the relief).
std::string GridSeriesWriter::xdmf() const {
  const std::string h5 = fs::path(path_).filename().string();
  std::string x =
      "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n <Domain>\n"
      "  <Grid Name=\"bed\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
  for (std::size_t k = 0; k < times_.size(); ++k) {
    x += fmt::format("   <Grid Name=\"frame{}\" GridType=\"Uniform\">\n    <Time Value=\"{:.17g}\"/>\n", k,
                     times_[k]);
    x += fmt::format("    <Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"{} {}\"/>\n", ny_, nx_);
    x += fmt::format(
        "    <Geometry GeometryType=\"ORIGIN_DXDY\">\n"
        "     <DataItem Dimensions=\"2\" Format=\"XML\">0 0</DataItem>\n"
        "     <DataItem Dimensions=\"2\" Format=\"XML\">{:.17g} {:.17g}</DataItem>\n    </Geometry>\n",
        dx_, dx_);
    x += fmt::format(
        "    <Attribute Name=\"{}\" AttributeType=\"Scalar\" Center=\"Node\">\n"
        "     <DataItem Dimensions=\"{} {}\" NumberType=\"Float\" Precision=\"8\" "
        "Format=\"HDF\">{}:/frames/{:06d}"
        "</DataItem>\n    </Attribute>\n   </Grid>\n",
        field_, ny_, nx_, h5, k);
  }
  return x + "  </Grid>\n </Domain>\n</Xdmf>\n";
}

}  // namespace grainlab
