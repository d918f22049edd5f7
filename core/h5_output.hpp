#pragma once
// Run output: HDF5 frames, energies and diagnostics with the metadata needed to reproduce the run,
// plus an XDMF sidecar so ParaView opens the particles directly. Everything is written under a
// temporary name and renamed into place when complete, so no half-written file is ever left.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace grainlab {

struct Frame {
  double time = 0;
  std::vector<std::int64_t> id;
  std::vector<double> position, velocity;  // N x 3 (z = 0 in 2-D, so ParaView reads them as points)
  std::vector<double> angle, spin, radius;
  std::vector<std::int32_t> shape;  // -1 disc, else polygon index into /shapes

  // Appends one 2-D body (z = 0).
  void add_body(std::int64_t body_id, double x, double y, double vx, double vy, double theta, double omega,
                double r, std::int32_t shape_index) {
    id.push_back(body_id);
    position.insert(position.end(), {x, y, 0.0});
    velocity.insert(velocity.end(), {vx, vy, 0.0});
    angle.push_back(theta);
    spin.push_back(omega);
    radius.push_back(r);
    shape.push_back(shape_index);
  }
};

struct RunMetadata {
  std::map<std::string, std::string> text;  // scene_text, version, units, effects, engine, ...
  std::map<std::string, double> numbers;    // seed, duration, ...
};

class RunWriter {
 public:
  // Fails (std::runtime_error) if `path` exists and !overwrite.
  RunWriter(std::string path, bool overwrite);
  ~RunWriter();
  RunWriter(const RunWriter&) = delete;
  RunWriter& operator=(const RunWriter&) = delete;

  void add_frame(Frame f) { frames_.push_back(std::move(f)); }
  void add_energy_row(const std::vector<double>& row) { energy_.push_back(row); }
  void set_energy_columns(std::vector<std::string> c) { energy_columns_ = std::move(c); }
  void set_polygons(std::vector<std::vector<double>> flat_vertices) { polygons_ = std::move(flat_vertices); }
  void set_metadata(RunMetadata m) { meta_ = std::move(m); }
  void set_diagnostics(std::map<std::string, double> d) { diagnostics_ = std::move(d); }
  // Writes the .h5 and .xmf atomically. Returns the .xmf path.
  std::string commit();

 private:
  void write_h5(const std::string& tmp) const;
  void write_xdmf(const std::string& tmp) const;

  std::string path_;
  std::vector<Frame> frames_;
  std::vector<std::vector<double>> energy_;
  std::vector<std::string> energy_columns_;
  std::vector<std::vector<double>> polygons_;
  RunMetadata meta_;
  std::map<std::string, double> diagnostics_;
};

// Writes `text` to `path` through a temporary file and a rename.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace grainlab
