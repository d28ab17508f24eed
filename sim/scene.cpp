// Scene loading: strict validation of the JSON scene schema (see scene.h and
// assets/scenes/*.json). Helpers throw `Invalid` internally; parse_scene turns it into an Error
// prefixed with the origin, so nothing escapes load_scene/parse_scene.
#include "sim/scene.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <set>
#include <span>
#include <string_view>

#include <nlohmann/json.hpp>

namespace aquaform {
namespace {

using json = nlohmann::json;

struct Invalid {
    std::string message;  // without the origin prefix
};

[[noreturn]] void fail(std::string message) { throw Invalid{std::move(message)}; }

constexpr std::string_view kTopKeys[] = {"name",         "domain", "particle_spacing", "rest_density",
                                         "gravity",      "fluid_blocks", "static_boxes", "frames",
                                         "column_width", "solver"};
constexpr std::string_view kBoxKeys[] = {"min", "max"};
constexpr std::string_view kSolverKeys[] = {"frame_dt",  "substeps", "iterations", "kernel_radius_factor",
                                            "relaxation", "viscosity", "vorticity", "scorr_k",
                                            "scorr_n",   "scorr_dq", "cfl"};

// ---- formatting ------------------------------------------------------------------------------

/// The value as the file wrote it (re-serialised compactly, long values shortened).
std::string written(const json& v) {
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

std::string kind_of(const json& v) {
    switch (v.type()) {
        case json::value_t::null: return "null";
        case json::value_t::boolean: return "a boolean";
        case json::value_t::string: return "a string";
        case json::value_t::object: return "an object";
        case json::value_t::array: return "an array of " + std::to_string(v.size()) + " elements";
        default: return "a number";
    }
}

std::string fmt(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    return buf;
}

std::string fmt(const glm::vec3& v) { return "[" + fmt(v.x) + "," + fmt(v.y) + "," + fmt(v.z) + "]"; }

std::string fmt(const Box& b) { return fmt(b.min) + ".." + fmt(b.max); }

std::string join(std::span<const std::string_view> keys) {
    std::string s;
    for (auto k : keys) s += (s.empty() ? "" : ", ") + std::string(k);
    return s;
}

constexpr const char* kAxis[] = {"x", "y", "z"};

// ---- keys ------------------------------------------------------------------------------------

size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diag = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            size_t up = row[j];
            bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                        std::tolower(static_cast<unsigned char>(b[j - 1]));
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (same ? 0 : 1)});
            diag = up;
        }
    }
    return row[b.size()];
}

/// `where` is "at top level" or "in <path>". Rejects keys outside `allowed`.
void check_keys(const json& obj, const std::string& where, std::span<const std::string_view> allowed) {
    for (const auto& [key, value] : obj.items()) {
        if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
        std::string_view best;
        size_t best_d = std::numeric_limits<size_t>::max();
        for (auto k : allowed) {
            size_t d = edit_distance(key, k);
            if (d < best_d) best_d = d, best = k;
        }
        std::string msg = "unknown key \"" + key + "\" " + where;
        if (best_d <= std::max<size_t>(2, best.size() / 3))
            msg += "; did you mean \"" + std::string(best) + "\"?";
        else
            msg += "; remove it.";
        fail(msg + " Allowed keys: " + join(allowed));
    }
}

void require(const json& obj, std::string_view key, const std::string& where, const std::string& example) {
    if (!obj.contains(key))
        fail("missing required key \"" + std::string(key) + "\" " + where + "; add it, e.g. " + example);
}

std::string child(const std::string& parent, std::string_view key) {
    return parent.empty() ? std::string(key) : parent + "." + std::string(key);
}

// ---- values ----------------------------------------------------------------------------------

/// A closed or open interval with the phrase that tells the user what to write.
struct Range {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;
    bool hi_open = false;
    const char* what = "a number";

    bool contains(double x) const {
        return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi) && std::isfinite(x);
    }
};

float read_number(const json& v, const std::string& path, const Range& r) {
    if (!v.is_number()) fail(path + " must be " + r.what + ", got " + written(v) + " (" + kind_of(v) + ")");
    double d = v.get<double>();
    if (!r.contains(d)) fail(path + " is " + written(v) + "; it must be " + r.what);
    float f = static_cast<float>(d);
    if (!r.contains(f) || std::fabs(f) > FLT_MAX)
        fail(path + " is " + written(v) + ", which a 32-bit float cannot hold; use a value between about 1e-30 "
             "and 1e30 (it must be " + r.what + ")");
    return f;
}

uint32_t read_integer(const json& v, const std::string& path, uint32_t lo, uint32_t hi) {
    std::string what = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
    if (!v.is_number()) fail(path + " must be " + what + ", got " + written(v) + " (" + kind_of(v) + ")");
    double d = v.get<double>();
    if (!std::isfinite(d) || std::floor(d) != d || d < lo || d > hi)
        fail(path + " is " + written(v) + "; it must be " + what);
    return static_cast<uint32_t>(d);
}

glm::vec3 read_vec3(const json& v, const std::string& path, const char* what) {
    if (!v.is_array() || v.size() != 3)
        fail(path + " must be " + what + ", got " + written(v) + " (" + kind_of(v) + ")");
    glm::vec3 out;
    for (int i = 0; i < 3; ++i) {
        std::string elem = path + "[" + std::to_string(i) + "]";
        const json& e = v[static_cast<size_t>(i)];
        if (!e.is_number())
            fail(elem + " must be a number, got " + written(e) + " (" + kind_of(e) + "); write " + path + " as " +
                 what);
        double d = e.get<double>();
        if (!std::isfinite(d) || std::fabs(d) > 1e30)
            fail(elem + " is " + written(e) + "; it must be a finite number between -1e30 and 1e30");
        out[i] = static_cast<float>(d);
    }
    return out;
}

/// Reads {"min": [..], "max": [..]} and checks max > min on every axis.
Box read_box(const json& v, const std::string& path, const std::string& example) {
    if (!v.is_object())
        fail(path + " must be an object {\"min\": [x, y, z], \"max\": [x, y, z]}, got " + written(v) + " (" +
             kind_of(v) + ")");
    check_keys(v, "in " + path, kBoxKeys);
    require(v, "min", "in " + path, example);
    require(v, "max", "in " + path, example);
    const char* what = "an array of three numbers [x, y, z] in metres";
    Box b{read_vec3(v["min"], path + ".min", what), read_vec3(v["max"], path + ".max", what)};
    for (int a = 0; a < 3; ++a)
        if (!(b.max[a] > b.min[a]))
            fail(path + " max " + written(v["max"]) + " is not greater than min " + written(v["min"]) + " on " +
                 kAxis[a] + "; make max larger than min on every axis");
    return b;
}

void check_inside(const Box& b, const json& v, const std::string& path, const Box& domain) {
    for (int a = 0; a < 3; ++a) {
        const char* side = b.min[a] < domain.min[a] ? "min" : b.max[a] > domain.max[a] ? "max" : nullptr;
        if (side)
            fail(path + " " + side + " " + written(v[side]) + " lies outside the domain " + fmt(domain) + " on " +
                 kAxis[a] + "; move the block inside the domain or enlarge \"domain\"");
    }
}

/// True when the boxes share a volume; boxes that only touch do not overlap.
bool overlaps(const Box& a, const Box& b) {
    for (int i = 0; i < 3; ++i)
        if (a.max[i] <= b.min[i] || b.max[i] <= a.min[i]) return false;
    return true;
}

// ---- lattice ---------------------------------------------------------------------------------

uint64_t saturating_mul(uint64_t a, uint64_t b) {
    uint64_t r;
    return __builtin_mul_overflow(a, b, &r) ? std::numeric_limits<uint64_t>::max() : r;
}

/// Points per axis: floor(extent / spacing + 1e-4), in double, saturated to uint64.
uint64_t lattice_points(float extent, float spacing) {
    if (!(spacing > 0.0f) || !(extent > 0.0f)) return 0;
    double n = std::floor(static_cast<double>(extent) / static_cast<double>(spacing) + 1e-4);
    if (!(n >= 0.0)) return 0;
    if (n >= 18446744073709551616.0) return std::numeric_limits<uint64_t>::max();
    return static_cast<uint64_t>(n);
}

uint64_t block_count(const Box& b, float spacing) {
    uint64_t n = 1;
    for (int a = 0; a < 3; ++a) n = saturating_mul(n, lattice_points(b.max[a] - b.min[a], spacing));
    return n;
}

// ---- the scene -------------------------------------------------------------------------------

constexpr const char* kBlockExample = "{\"min\": [0, 0, 0], \"max\": [0.3, 0.6, 0.2]}";

void read_solver(const json& s, SolverSettings& out) {
    if (!s.is_object())
        fail("solver must be an object such as {\"substeps\": 3, \"iterations\": 4}, got " + written(s) + " (" +
             kind_of(s) + ")");
    check_keys(s, "in solver", kSolverKeys);
    struct FloatKey {
        const char* key;
        float SolverSettings::*member;
        Range range;
    };
    const FloatKey floats[] = {
        {"frame_dt", &SolverSettings::frame_dt,
         {0.0, 0.1, true, false, "a number of seconds greater than 0 and at most 0.1, e.g. 0.0166667 (1/60 s)"}},
        {"kernel_radius_factor", &SolverSettings::kernel_radius_factor,
         {1.0, 4.0, false, false, "a number from 1.0 to 4.0 (h = factor * particle_spacing; 2.0 is usual)"}},
        {"relaxation", &SolverSettings::relaxation, {0.0, HUGE_VAL, true, false, "a positive number, e.g. 0.01 (relative to the stiffness of a full neighbourhood)"}},
        {"viscosity", &SolverSettings::viscosity, {0.0, 1.0, false, false, "a number from 0 to 1, e.g. 0.01"}},
        {"vorticity", &SolverSettings::vorticity,
         {0.0, HUGE_VAL, false, false, "a number >= 0, e.g. 0.0001 (0 turns it off)"}},
        {"scorr_k", &SolverSettings::scorr_k, {0.0, HUGE_VAL, false, false, "a number >= 0, e.g. 0.1 (0 turns it off)"}},
        {"scorr_n", &SolverSettings::scorr_n, {1.0, HUGE_VAL, false, false, "a number >= 1, e.g. 4"}},
        {"scorr_dq", &SolverSettings::scorr_dq,
         {0.0, 1.0, true, true, "a number strictly between 0 and 1 (a fraction of h), e.g. 0.2"}},
        {"cfl", &SolverSettings::cfl, {0.0, 1.0, true, false, "a number greater than 0 and at most 1, e.g. 0.4"}},
    };
    for (const auto& f : floats)
        if (s.contains(f.key)) out.*f.member = read_number(s[f.key], child("solver", f.key), f.range);
    if (s.contains("substeps")) out.substeps = read_integer(s["substeps"], "solver.substeps", 1, 64);
    if (s.contains("iterations")) out.iterations = read_integer(s["iterations"], "solver.iterations", 1, 100);
}

std::vector<Box> read_boxes(const json& v, const std::string& key, const Box& domain) {
    if (!v.is_array())
        fail(key + " must be an array of boxes such as [" + kBlockExample + "], got " + written(v) + " (" +
             kind_of(v) + ")");
    std::vector<Box> boxes;
    for (size_t i = 0; i < v.size(); ++i) {
        std::string path = key + "[" + std::to_string(i) + "]";
        boxes.push_back(read_box(v[i], path, "\"max\": [0.3, 0.6, 0.2]"));
        check_inside(boxes.back(), v[i], path, domain);
    }
    return boxes;
}

Scene read_scene(const json& j) {
    if (!j.is_object())
        fail("the top level must be a JSON object {\"name\": ..., \"domain\": ..., ...}, got " + written(j) + " (" +
             kind_of(j) + "); see assets/scenes/dam_break.json for an example");
    check_keys(j, "at top level", kTopKeys);
    const std::string top = "at top level";
    require(j, "name", top, "\"name\": \"dam break\"");
    require(j, "domain", top, "\"domain\": {\"min\": [0, 0, 0], \"max\": [1.6, 0.8, 0.2]}");
    require(j, "particle_spacing", top, "\"particle_spacing\": 0.02");
    require(j, "fluid_blocks", top, "\"fluid_blocks\": [" + std::string(kBlockExample) + "]");

    Scene scene;
    const json& name = j["name"];
    if (!name.is_string() || name.get<std::string>().empty())
        fail("name must be a non-empty string, e.g. \"dam break\", got " + written(name) + " (" + kind_of(name) + ")");
    scene.name = name.get<std::string>();

    scene.domain = read_box(j["domain"], "domain", "\"max\": [1.6, 0.8, 0.2]");
    scene.particle_spacing =
        read_number(j["particle_spacing"], "particle_spacing", {0.0, HUGE_VAL, true, false,
                                                                "a positive number of metres, e.g. 0.02"});
    if (j.contains("rest_density"))
        scene.rest_density = read_number(j["rest_density"], "rest_density",
                                         {0.0, HUGE_VAL, true, false, "a positive number in kg/m^3, e.g. 1000 for water"});
    if (j.contains("gravity"))
        scene.gravity = read_vec3(j["gravity"], "gravity", "an array of three numbers [x, y, z] in m/s^2, e.g. [0, -9.81, 0]");
    if (j.contains("frames")) scene.frames = read_integer(j["frames"], "frames", 1, 1000000);
    if (j.contains("solver")) read_solver(j["solver"], scene.solver);

    if (j.contains("static_boxes")) scene.static_boxes = read_boxes(j["static_boxes"], "static_boxes", scene.domain);
    const json& blocks = j["fluid_blocks"];
    scene.fluid_blocks = read_boxes(blocks, "fluid_blocks", scene.domain);
    if (scene.fluid_blocks.empty())
        fail("fluid_blocks is [] (empty); add at least one block, e.g. [" + std::string(kBlockExample) + "]");

    for (size_t i = 0; i < scene.fluid_blocks.size(); ++i) {
        const Box& b = scene.fluid_blocks[i];
        std::string path = "fluid_blocks[" + std::to_string(i) + "]";
        for (int a = 0; a < 3; ++a)
            if (lattice_points(b.max[a] - b.min[a], scene.particle_spacing) == 0)
                fail(path + " " + fmt(b) + " is thinner on " + kAxis[a] + " than particle_spacing " +
                     written(j["particle_spacing"]) + ", so it holds no particles; widen the block or reduce "
                     "particle_spacing");
        for (size_t s = 0; s < scene.static_boxes.size(); ++s)
            if (overlaps(b, scene.static_boxes[s]))
                fail(path + " " + fmt(b) + " overlaps static_boxes[" + std::to_string(s) + "] " +
                     fmt(scene.static_boxes[s]) + "; fluid cannot start inside a solid: shrink or move the block "
                     "(boxes may touch)");
        for (size_t k = 0; k < i; ++k)
            if (overlaps(b, scene.fluid_blocks[k]))
                fail(path + " " + fmt(b) + " overlaps fluid_blocks[" + std::to_string(k) + "] " +
                     fmt(scene.fluid_blocks[k]) + ", which would place particles on top of each other; make the "
                     "blocks disjoint (they may touch)");
    }

    if (j.contains("column_width")) {
        const json& cw = j["column_width"];
        float a = read_number(cw, "column_width", {0.0, HUGE_VAL, true, false,
                                                   "a positive number of metres (the x-extent of fluid_blocks[0])"});
        const Box& b = scene.fluid_blocks[0];
        float extent = b.max.x - b.min.x;
        if (std::fabs(a - extent) > 1e-4f * std::max(a, extent))
            fail("column_width is " + written(cw) + " but fluid_blocks[0] is " + fmt(extent) + " m wide on x (" +
                 fmt(b) + "); set column_width to " + fmt(extent) + " or resize the block");
        if (std::fabs(b.min.x - scene.domain.min.x) > 0.5f * scene.particle_spacing)
            fail("column_width is " + written(cw) + " but fluid_blocks[0] starts at x = " + fmt(b.min.x) +
                 ", not against the wall at domain.min.x = " + fmt(scene.domain.min.x) +
                 "; move the block to the wall or remove column_width");
        scene.column_width = a;
    }

    uint64_t count = scene.particle_count();
    if (count > kMaxSceneParticles)
        fail("the fluid blocks hold " + (count < 1000000000000ull ? std::to_string(count) : fmt(double(count))) +
             " particles at particle_spacing " +
             written(j["particle_spacing"]) + ", more than the limit of " + std::to_string(kMaxSceneParticles) +
             "; increase particle_spacing or shrink fluid_blocks");
    return scene;
}

/// nlohmann reports "... at line L, column C: what"; keep the "line L, column C" and "what" parts.
std::string syntax_error(const json::parse_error& e, const std::string& origin) {
    std::string msg = e.what();
    size_t at = msg.find("line ");
    size_t colon = msg.find(": ", at == std::string::npos ? 0 : at);
    std::string where = "byte " + std::to_string(e.byte);
    std::string what = msg;
    if (at != std::string::npos && colon != std::string::npos) {
        where = msg.substr(at, colon - at);
        what = msg.substr(colon + 2);
    }
    return origin + ": invalid JSON at " + where + ": " + what +
           "; fix the syntax there (look for a missing or trailing comma, an unclosed bracket or an unquoted key)";
}

/// nlohmann throws "number overflow parsing '1e400'" without a position; find the literal.
std::string number_overflow(const json::exception& e, const std::string& text, const std::string& origin) {
    std::string msg = e.what();
    if (size_t p = msg.find("] "); p != std::string::npos) msg = msg.substr(p + 2);
    std::string where;
    size_t q1 = msg.find('\''), q2 = msg.rfind('\'');
    if (q1 != std::string::npos && q2 > q1) {
        size_t at = text.find(msg.substr(q1 + 1, q2 - q1 - 1));
        if (at != std::string::npos)
            where = " at line " + std::to_string(1 + std::count(text.begin(), text.begin() + at, '\n'));
    }
    return origin + ": cannot read the JSON" + where + ": " + msg +
           "; use numbers of ordinary size (a 32-bit float holds up to about 3e38)";
}

}  // namespace

uint64_t Scene::particle_count() const {
    uint64_t total = 0;
    for (const Box& b : fluid_blocks) {
        uint64_t n = block_count(b, particle_spacing);
        total = n > std::numeric_limits<uint64_t>::max() - total ? std::numeric_limits<uint64_t>::max() : total + n;
    }
    return total;
}

void Scene::generate_particles(std::vector<glm::vec4>& positions, std::vector<uint32_t>& block_of) const {
    positions.clear();
    block_of.clear();
    uint64_t total = particle_count();
    positions.reserve(total);  // throws std::length_error for absurd counts instead of looping forever
    block_of.reserve(total);
    const double s = particle_spacing;
    for (size_t bi = 0; bi < fluid_blocks.size(); ++bi) {
        const Box& b = fluid_blocks[bi];
        uint64_t n[3];
        for (int a = 0; a < 3; ++a) n[a] = lattice_points(b.max[a] - b.min[a], particle_spacing);
        for (uint64_t k = 0; k < n[2]; ++k)
            for (uint64_t j = 0; j < n[1]; ++j)
                for (uint64_t i = 0; i < n[0]; ++i) {
                    positions.emplace_back(static_cast<float>(b.min.x + s * (i + 0.5)),
                                           static_cast<float>(b.min.y + s * (j + 0.5)),
                                           static_cast<float>(b.min.z + s * (k + 0.5)), 0.0f);
                    block_of.push_back(static_cast<uint32_t>(bi));
                }
    }
}

Result<Scene> parse_scene(const std::string& json_text, const std::string& origin) {
    try {
        // Duplicate keys are legal JSON but nlohmann silently keeps the last; a scene file with
        // two "particle_spacing" entries is a mistake, so report it.
        std::vector<std::set<std::string>> open_objects;
        std::optional<std::string> duplicate;
        auto on_event = [&](int, json::parse_event_t event, json& parsed) {
            if (event == json::parse_event_t::object_start) open_objects.emplace_back();
            if (event == json::parse_event_t::object_end && !open_objects.empty()) open_objects.pop_back();
            if (event == json::parse_event_t::key && !open_objects.empty() && !duplicate &&
                !open_objects.back().insert(parsed.get<std::string>()).second)
                duplicate = parsed.get<std::string>();
            return true;
        };
        json j = json::parse(json_text, on_event);
        if (duplicate)
            return Error{origin + ": duplicate key \"" + *duplicate +
                         "\" (written twice in the same object, and only the last would count); keep one of them"};
        return read_scene(j);
    } catch (const Invalid& e) {
        return Error{origin + ": " + e.message};
    } catch (const json::parse_error& e) {
        return Error{syntax_error(e, origin)};
    } catch (const json::exception& e) {
        return Error{number_overflow(e, json_text, origin)};
    } catch (const std::exception& e) {
        return Error{origin + ": " + std::string(e.what())};
    }
}

Result<Scene> load_scene(const std::filesystem::path& path) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        return Error{"cannot open scene file \"" + path.string() + "\"" +
                     (std::filesystem::is_directory(path, ec) ? " (it is a directory)" : "") +
                     "; check the path (scenes live in assets/scenes/)"};
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof())
        return Error{"cannot read scene file \"" + path.string() + "\"; check that it is readable "
                     "(scenes live in assets/scenes/)"};
    Result<Scene> scene = parse_scene(text, path.string());
    if (scene) scene.value().path = path;
    return scene;
}

}  // namespace aquaform
