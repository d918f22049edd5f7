#include "effects.hpp"

#include <stdexcept>

namespace grainlab {

const std::vector<EffectInfo>& effect_registry() {
  static const std::vector<EffectInfo> all = {
      {Effect::gravity,
       "gravity",
       "uniform gravity, [scene] gravity",
       {},
       {"scene.gravity"},
       "body forces: m g, restarted with every force evaluation",
       "single-body (free flight), block-incline"},
      {Effect::normal_contact,
       "normal_contact",
       "spring-dashpot normal force (eq. 2.3)",
       {},
       {"materials.k_n", "materials.gamma_n|damping_n|restitution"},
       "pair kernels: all_contacts<...>",
       "thesis-code, pair-impact"},
      {Effect::friction,
       "friction",
       "shear spring capped at mu f_n (Coulomb)",
       {Effect::normal_contact},
       {"materials.k_s", "materials.mu", "materials.gamma_s|damping_s"},
       "pair kernels: all_contacts<Friction = true>",
       "block-incline, tumbling-polygon"},
      {Effect::rotation,
       "rotation",
       "bodies turn (torques, spins)",
       {},
       {},
       "pair kernels: all_contacts<Rotation = true>; the integrators' angular pass",
       "tumbling-polygon"},
      {Effect::wind_drag,
       "wind_drag",
       "drag of a 1-D wind profile u(y) on each grain (eqs 4.30-4.31 or a selectable law); the wind's "
       "shear stress reduced by the grains' drag (Ch. IV feedback)",
       {},
       {"wind", "fluid"},
       "body forces: native_dem/wind.cpp (WindField::add_drag), updated every "
       "[wind] update_interval",
       "dem-saltation (momentum balance, grain-free log law, terminal velocity)"},
      {Effect::buoyancy,
       "buoyancy",
       "gravity reduced by (1 - rho_fluid / rho_grain)",
       {Effect::gravity},
       {"fluid.density", "fluid.grain_density"},
       "body forces: the gravity constant scaled once",
       "dem-saltation (terminal velocity)"},
  };
  return all;
}

const EffectInfo& effect_info(Effect e) {
  for (const EffectInfo& i : effect_registry())
    if (i.id == e) return i;
  throw std::logic_error("effect missing from the registry");
}

std::optional<Effect> effect_named(std::string_view name) {
  for (const EffectInfo& i : effect_registry())
    if (i.name == name) return i.id;
  return std::nullopt;
}

std::vector<std::string> known_effect_names() {
  std::vector<std::string> n;
  for (const EffectInfo& i : effect_registry()) n.push_back(i.name);
  return n;
}

std::vector<std::string> Effects::names() const {
  std::vector<std::string> n;
  for (const EffectInfo& i : effect_registry())
    if (has(i.id)) n.push_back(i.name);
  return n;
}

}  // namespace grainlab
