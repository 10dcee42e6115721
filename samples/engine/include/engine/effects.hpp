// Which effects a scene calls for, derived once at load time (docs/design.md:
// "simulate only what the scene calls for"). The tracer compiles one kernel
// per combination; an absent effect is not in the hot path at all.
#pragma once

#include <engine/scene.hpp>

#include <cstdint>
#include <optional>
#include <string>

namespace foveart::engine {

struct Effects {
  bool shadows = false;     // punctual lights exist -> direct light with shadow rays
  bool reflection = false;  // a used material is mirror-like -> reflection rays
  bool refraction = false;  // a used material transmits -> refraction rays
  bool textures = false;    // a used material has a base colour texture and uvs exist

  uint32_t bits() const {
    return (shadows ? 1u : 0u) | (reflection ? 2u : 0u) | (refraction ? 4u : 0u) |
           (textures ? 8u : 0u);
  }
  static Effects from_bits(uint32_t b) {
    return Effects{(b & 1u) != 0, (b & 2u) != 0, (b & 4u) != 0, (b & 8u) != 0};
  }
  Effects operator&(const Effects& o) const { return from_bits(bits() & o.bits()); }
  bool operator==(const Effects&) const = default;
  static Effects all() { return from_bits(15u); }
  static Effects none() { return from_bits(0u); }
};

// Looks only at materials that triangles actually use.
Effects derive_effects(const Scene& scene);

std::string to_string(const Effects& e);  // e.g. "shadows+reflection"; "primary-only" for none

// The effects a list names: shadows, reflection, refraction, textures,
// separated by ',' or '+' (so to_string's output reads back), or
// "primary-only" for none. nullopt with *error naming the first unknown name.
std::optional<Effects> parse_effects(const std::string& names, std::string* error);

}  // namespace foveart::engine
