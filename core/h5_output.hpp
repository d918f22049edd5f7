#pragma once
// Run output: HDF5 frames, energies and diagnostics with the metadata needed to reproduce the run,
// plus an XDMF sidecar so ParaView opens the particles directly. Everything is written under a
// temporary name and renamed into place when complete, so no half-written file is ever left.
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "interrupt.hpp"

namespace grainlab {

struct Frame {
  double time = 0;
  std::vector<std::int64_t> id;
  std::vector<double> position, velocity;  // N x 3 (z = 0 in 2-D, so ParaView reads them as points)
  std::vector<double> angle, spin;         // 2-D only
  std::vector<double> orientation;         // N x 4 unit quaternions (w, x, y, z), body to world
  std::vector<double> angular_velocity;    // N x 3, world frame
  std::vector<double> radius;
  std::vector<std::int32_t> shape;  // -1 disc or sphere, else index into /shapes

  // Appends one 2-D body (z = 0).
  void add_body(std::int64_t body_id, double x, double y, double vx, double vy, double theta, double omega,
                double r, std::int32_t shape_index) {
    id.push_back(body_id);
    position.insert(position.end(), {x, y, 0.0});
    velocity.insert(velocity.end(), {vx, vy, 0.0});
    angle.push_back(theta);
    spin.push_back(omega);
    orientation.insert(orientation.end(), {std::cos(theta / 2), 0.0, 0.0, std::sin(theta / 2)});
    angular_velocity.insert(angular_velocity.end(), {0.0, 0.0, omega});
    radius.push_back(r);
    shape.push_back(shape_index);
  }
  // Appends one 3-D body; q is (w, x, y, z), shape_index -1 for a sphere, else into /shapes.
  void add_body3d(std::int64_t body_id, const double x[3], const double v[3], const double q[4],
                  const double w[3], double r, std::int32_t shape_index) {
    id.push_back(body_id);
    position.insert(position.end(), x, x + 3);
    velocity.insert(velocity.end(), v, v + 3);
    orientation.insert(orientation.end(), q, q + 4);
    angular_velocity.insert(angular_velocity.end(), w, w + 3);
    radius.push_back(r);
    shape.push_back(shape_index);
  }
};

struct RunMetadata {
  std::map<std::string, std::string> text;  // scene_text, version, units, effects, engine, ...
  std::map<std::string, double> numbers;    // seed, duration, ...
};

// Contact events as columns (one row per event), in scene units.
struct ContactEventTable {
  std::vector<std::int64_t> body_a, body_b;  // body ids; a wall or plane k is -1 - k (always body_b)
  std::vector<double> t_begin, t_end, normal_impulse, peak_force;
  std::vector<std::int32_t> open;  // 1: still touching when the run ended
};

// Frames are streamed: each is written and flushed when added, so memory does not grow with the run (100
// frames of 100,000 spheres would hold over a gigabyte). The file lives under a temporary name until
// commit(); destroyed uncommitted, the writer removes it (no half-written output).
class RunWriter {
 public:
  // Fails (std::runtime_error) if `path` exists and !overwrite.
  RunWriter(std::string path, bool overwrite);
  ~RunWriter();
  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;

  void add_frame(const Frame& f);
  std::size_t frames() const { return index_.size(); }
  // Copies the frames written so far into group `group` (created) of the open HDF5 file `dest`, as
  // /frames/NNNNNN are here: a checkpoint carries them without holding them in memory.
  void copy_frames(std::int64_t dest, const std::string& group);
  void add_energy_row(const std::vector<double>& row) { energy_.push_back(row); }
  void set_energy_columns(std::vector<std::string> c) { energy_columns_ = std::move(c); }
  // Body-frame vertices of each polygon (x, y) or polyhedron (x, y, z), flattened.
  void set_polygons(std::vector<std::vector<double>> flat_vertices, int columns = 2) {
    polygons_ = std::move(flat_vertices);
    shape_columns_ = columns;
  }
  void set_metadata(RunMetadata m) { meta_ = std::move(m); }
  void set_diagnostics(std::map<std::string, double> d) { diagnostics_ = std::move(d); }
  // Written as /contact_events when set (the scene asked for [output] contacts = true).
  void set_contact_events(ContactEventTable t) { contacts_ = std::move(t); }
  // Writes the rest of the .h5 and the .xmf, and renames both into place. Returns the .xmf path.
  std::string commit();

 private:
  void finish_h5();
  void write_xdmf(const std::string& tmp) const;

  // What the XDMF sidecar and /frames/time need of a frame already written.
  struct WrittenFrame {
    double time;
    std::size_t bodies;
    bool planar;  // has 2-D angle and spin
  };
  std::string path_, tmp_;
  TempFileHold hold_{tmp_};  // removed if the run is stopped by a signal
  std::int64_t file_ = -1;
  bool committed_ = false;
  std::vector<WrittenFrame> index_;
  std::vector<std::vector<double>> energy_;
  std::vector<std::string> energy_columns_;
  std::vector<std::vector<double>> polygons_;
  int shape_columns_ = 2;
  RunMetadata meta_;
  std::map<std::string, double> diagnostics_;
  std::optional<ContactEventTable> contacts_;
};

// A table of raw samples (one row per run, named columns), for validation studies' results.h5.
struct SampleTable {
  std::string name;  // dataset path below the root, e.g. "loaded_die_2d/native"
  std::string description;
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
};

// Writes the tables to `path` atomically: one 2-D dataset per table with attributes "columns"
// (comma-separated) and "description", plus string attributes `metadata` on the root. `extra`, when
// given, adds what tables cannot hold to the open file (its HDF5 id) before it is closed.
void write_sample_tables(const std::string& path, const std::vector<SampleTable>& tables,
                         const std::map<std::string, std::string>& metadata,
                         const std::function<void(std::int64_t)>& extra = {});

// A time series of 2-D grids (a bed's heights, x fastest) streamed to HDF5 as it is taken: each frame is
// written and flushed when added, so memory does not grow with the run; the file lives under a temporary
// name until commit() adds the tables and metadata, writes the XDMF sidecar and renames both into place.
// Destroyed uncommitted, it removes the temporary (no half-written output).
class GridSeriesWriter {
 public:
  // Fails (std::runtime_error) if `path` exists and !overwrite.
  GridSeriesWriter(std::string path, bool overwrite, std::size_t nx, std::size_t ny, double dx,
                   std::string field);
  ~GridSeriesWriter();
  GridSeriesWriter(const GridSeriesWriter&) = delete;
  GridSeriesWriter& operator=(const GridSeriesWriter&) = delete;
  void add_frame(double time, const std::vector<double>& values);
  // Returns the .xmf path.
  std::string commit(const std::vector<SampleTable>& tables,
                     const std::map<std::string, std::string>& metadata);

 private:
  std::string xdmf() const;
  std::string path_, tmp_, field_;
  TempFileHold hold_{tmp_};  // removed if the run is stopped by a signal
  std::size_t nx_, ny_;
  double dx_;
  std::int64_t file_ = -1;
  std::vector<double> times_;
  bool committed_ = false;
};

// Writes `text` to `path` through a temporary file and a rename.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace grainlab
