#pragma once
// The registry of physical effects. A scene lists the effects it needs; each engine declares the ones it
// really models (backends/capabilities.cpp) and refuses a scene asking for more; the native engine runs
// the kernels of the active ones only. Adding an effect: one enumerator, one registry row (effects.cpp),
// its scene keys (scene.cpp) and its kernel (docs/architecture.md, "Adding an effect").
#include <bitset>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace grainlab {

enum class Effect : unsigned { gravity, normal_contact, friction, rotation, wind_drag, buoyancy, count };
inline constexpr std::size_t kEffectCount = static_cast<std::size_t>(Effect::count);

struct EffectInfo {
  Effect id;
  std::string name;
  std::string summary;                  // one line, for docs and `grainlab engines`
  std::vector<Effect> needs;            // effects that must be listed with it
  std::vector<std::string> scene_keys;  // the scene tables/keys it reads
  std::string kernel;                   // where the native engine applies it
  std::string validation;               // what checks it
};

// Every effect, in documentation order.
const std::vector<EffectInfo>& effect_registry();
const EffectInfo& effect_info(Effect e);
std::optional<Effect> effect_named(std::string_view name);
// Every effect name a scene may list, in documentation order.
std::vector<std::string> known_effect_names();

// The set of effects a scene asks for.
class Effects {
 public:
  bool has(Effect e) const { return bits_.test(static_cast<std::size_t>(e)); }
  void set(Effect e, bool on = true) { bits_.set(static_cast<std::size_t>(e), on); }
  std::vector<std::string> names() const;
  bool operator==(const Effects&) const = default;

 private:
  std::bitset<kEffectCount> bits_;
};

}  // namespace grainlab
