#pragma once
// The wind of effect wind_drag: a horizontally averaged wind u(y) over a periodic 2-D bed that drags
// each grain (as the sphere it stands for) and is slowed by their drag in return: the thesis's Ch. IV
// feedback in the time-dependent form of DEM saltation models (Duran et al. 2012, Carneiro et al.
// 2011): rho_f du/dt = d tau_f/dz - (drag of the grains per volume), tau_f = rho_f l^2 |du/dz| du/dz.
// Between updates the wind is frozen while each grain's drag rate is tallied per height cell; every
// [wind] update_interval the column is solved again, implicitly with that drag linearised in u: steady
// (the default) or advanced by the interval ([wind] inertia = true).
//
// Conservation: each grain's drag rate is tallied into the two cells its wind is interpolated from, with
// the interpolation's weights, so the column's sum of a u - b is the grains' own drag at the column's
// speeds. (Tallied by the cell holding the grain's centre instead, the bed's dense top cell was charged
// for the wind of the cell above, and the wind lost 2.4-3.2 % less than the grains gained at u* = 35.)
// What remains is the lag: the grains felt the wind of the previous update, the column charges the new
// one; it averages out (under 0.1 % of the drag over a run).
//
// Rank independence: a grain's drag depends only on its own state and the (replicated) wind; the
// tallies are summed in fixed point, so the wind is bitwise the same on any number of ranks.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "particles.hpp"
#include "scene.hpp"

namespace grainlab::dem {

class WindField {
 public:
  // Resolves the spec's defaults (roughness, cells, top, slab thickness) from the grains' median radius
  // and starts from the clean log law over the bed. `n` particles of `p` are all the world's (before
  // any distribution). Throws InputError when the scene cannot carry the wind (feedback without
  // periodic_x, no grains).
  WindField(const Scene& scene, const Particles& p, std::size_t n);

  // Adds the current wind's drag to the forces of particles [0, n) and keeps each one's drag rate.
  void add_drag(Particles& p, std::size_t n);
  // After an accepted step: tallies the step's drag; at an update time advances the wind (collective in
  // a distributed world: every rank calls it with its owned particles).
  void after_step(const Particles& p, std::size_t n, double t, double dt, bool distributed);

  struct Snapshot {
    std::vector<double> y, u, u_clean;  // cell centres (absolute height) and the wind there
    std::vector<double> grain_stress;   // drag of the grains above each cell's lower face per bed area
                                        // over the last interval (dyn/cm^2)
    double bed_level = 0;               // absolute height of the bed surface (10 ms running mean)
    double u_star_eff = 0;        // sqrt(tau_f / rho) one median diameter above the bed level (the surface
                                  // grains' tops): the shear velocity the grains leave the air
    double drag_per_area = 0;     // what the wind lost to the grains per bed area over the last interval
    double applied_per_area = 0;  // what the engine gave the grains by drag over it (the grains' view;
                                  // differs from the wind's by the wind's change over the interval)
    // (rho u*_eff^2 + grain-borne stress) / rho u*^2 on that face: 1 when the column has converged.
    double stress_partition = 1;
    double time = 0;  // of the last update
    int updates = 0;
  };
  const Snapshot& snapshot() const { return snap_; }
  // Wind speed at absolute height y.
  double u_at(double y) const;
  double bed_area() const { return width_ * thickness_; }
  const WindSpec& spec() const { return w_; }

  // Checkpoints: everything that the next steps depend on, and back. The tallies of the interval under
  // way are summed over the ranks by save (collective when distributed) and kept by one rank on restore
  // (`keep_tallies`; the others start theirs at zero), so the sums at the next update are the same.
  std::vector<double> save(bool distributed) const;
  void restore(const std::vector<double>& s, bool keep_tallies);

 private:
  void update(const Particles& p, std::size_t n, double t, bool distributed);
  double find_bed_level(const std::vector<std::uint64_t>& counts) const;
  std::size_t cell_of(double y) const;
  std::vector<double> heights_above_bed() const;

  WindSpec w_;
  FluidSpec f_;
  double width_ = 0, thickness_ = 0, dy_ = 0, y_lo_ = 0, diameter_ = 0;
  std::size_t cells_ = 0;
  // Fixed-point tallies per cell of m c dt (g) and m c v dt (g cm/s), c the drag rate, and their units.
  double unit_a_ = 1, unit_b_ = 1;
  std::vector<std::int64_t> tally_a_, tally_b_;
  std::vector<std::int64_t> tally_applied_;     // x-impulse the grains received per cell, unit_b_
  std::vector<double> eddy_;                    // the column's face eddy viscosities (its solver's memory)
  std::vector<double> rate_, rate_v_, drag_x_;  // per particle at the latest evaluation: m c, m c v_x, f_x
  struct Stencil {
    std::uint32_t cell;  // the lower of the two cells the wind is interpolated from
    double upper;        // the weight of the upper one
  };
  Stencil stencil_of(double y) const;
  std::vector<Stencil> stencil_;  // per particle at the latest evaluation
  double last_update_ = 0, next_update_ = 0;
  Snapshot snap_;
};

}  // namespace grainlab::dem
