#include "sim/whitewater_spec.h"

#include <algorithm>
#include <string_view>

#include "core/json_fields.h"

namespace aquaform {

namespace {

using namespace json_fields;

constexpr std::string_view kWhitewaterKeys[] = {
    "enabled",  "capacity",    "trapped_air",  "wave_crest",         "kinetic_energy", "k_trapped_air", "k_wave_crest",
    "lifetime", "spray_below", "bubble_above", "emit_min_neighbors", "air_drag",       "buoyancy",      "bubble_drag"};

/// The largest pool a scene may ask for: 16 Mi particles (1 GiB).
constexpr uint32_t kMaxCapacity = 1u << 24;

/// [lo, hi] with 0 <= lo < hi.
glm::vec2 read_range(const json& v, const std::string& path, const char* unit) {
    if (!v.is_array() || v.size() != 2) fail(path + " must be a range [low, high] " + unit + ", got " + written(v));
    const Range non_negative{0.0, 1e9, false, false, std::string("a number from 0 ") + unit};
    const float lo = read_number(v[0], path + "[0]", non_negative), hi = read_number(v[1], path + "[1]", non_negative);
    if (!(hi > lo))
        fail(path + " is " + written(v) + "; its high end must be above its low end, e.g. [" + fmt(lo) + ", " +
             fmt(lo + 1.0) + "]");
    return {lo, hi};
}

}  // namespace

WhitewaterSettings read_whitewater(const json& v) {
    if (!v.is_object()) fail("whitewater must be an object such as {\"enabled\": true}, got " + written(v));
    check_keys(v, "in whitewater", kWhitewaterKeys);
    WhitewaterSettings s;
    if (v.contains("enabled")) {
        if (!v["enabled"].is_boolean()) fail("whitewater.enabled must be true or false, got " + written(v["enabled"]));
        s.enabled = v["enabled"].get<bool>();
    }
    if (v.contains("capacity")) s.capacity = read_integer(v["capacity"], "whitewater.capacity", 0, kMaxCapacity);
    if (v.contains("trapped_air")) s.trapped_air = read_range(v["trapped_air"], "whitewater.trapped_air", "(m/s)");
    if (v.contains("wave_crest")) s.wave_crest = read_range(v["wave_crest"], "whitewater.wave_crest", "(curvature)");
    if (v.contains("kinetic_energy"))
        s.kinetic_energy = read_range(v["kinetic_energy"], "whitewater.kinetic_energy", "(J/kg)");
    if (v.contains("lifetime")) s.lifetime = read_range(v["lifetime"], "whitewater.lifetime", "(s)");
    const Range rate{0.0, 1e9, false, false, "a number of whitewater particles a second, from 0"};
    if (v.contains("k_trapped_air"))
        s.k_trapped_air = read_number(v["k_trapped_air"], "whitewater.k_trapped_air", rate);
    if (v.contains("k_wave_crest")) s.k_wave_crest = read_number(v["k_wave_crest"], "whitewater.k_wave_crest", rate);
    if (v.contains("spray_below")) s.spray_below = read_integer(v["spray_below"], "whitewater.spray_below", 0, 1000);
    if (v.contains("bubble_above"))
        s.bubble_above = read_integer(v["bubble_above"], "whitewater.bubble_above", 0, 1000);
    if (s.bubble_above < s.spray_below)
        fail("whitewater.bubble_above (" + std::to_string(s.bubble_above) + ") is below whitewater.spray_below (" +
             std::to_string(s.spray_below) + "); foam lies between them: raise bubble_above or lower spray_below");
    if (v.contains("emit_min_neighbors"))
        s.emit_min_neighbors = read_integer(v["emit_min_neighbors"], "whitewater.emit_min_neighbors", 0, 1000);
    if (v.contains("air_drag"))
        s.air_drag = read_number(v["air_drag"], "whitewater.air_drag",
                                 {0.0, 1000.0, false, false, "a rate from 0 to 1000 per second"});
    if (v.contains("buoyancy"))
        s.buoyancy = read_number(v["buoyancy"], "whitewater.buoyancy",
                                 {0.0, 100.0, false, false, "a multiple of g from 0 to 100"});
    if (v.contains("bubble_drag"))
        s.bubble_drag =
            read_number(v["bubble_drag"], "whitewater.bubble_drag", {0.0, 1.0, false, false, "a share from 0 to 1"});
    return s;
}

uint32_t whitewater_capacity(const WhitewaterSettings& settings, uint64_t fluid_particles, uint64_t device_bytes) {
    if (settings.capacity > 0) return settings.capacity;
    const uint64_t wanted = std::max<uint64_t>(65536, 4 * fluid_particles);
    const uint64_t affordable = std::max<uint64_t>(1024, device_bytes / 16 / 64);
    return uint32_t(std::min<uint64_t>({wanted, affordable, kMaxCapacity}));
}

}  // namespace aquaform
