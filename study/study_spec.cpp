#include "study/study_spec.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string_view>

#include "bench/bench_frames.h"
#include "core/file_name.h"
#include "core/json_fields.h"
#include "render/picture_size.h"
#include "render/registry.h"
#include "render/surface_settings.h"
#include "sim/scene.h"

namespace aquaform::study {

namespace {

using namespace json_fields;
namespace fs = std::filesystem;

constexpr std::array<std::string_view, 4> kTopKeys{"name", "repeats", "cases", "solver_map"};
constexpr std::array<std::string_view, 9> kCaseKeys{
    "name", "scene", "particles", "time", "camera", "resolutions", "methods", "note", "list_bytes_per_pixel"};
constexpr std::array<std::string_view, 8> kMethodKeys{"method",    "visual",     "size",     "recursion",
                                                      "bisection", "resolution", "stepping", "surface"};
constexpr std::array<std::string_view, 5> kMapKeys{"scene", "dt", "iterations", "control_pressure", "time"};

/// "the metaball methods (brute, abuffer, sbuffer)": the registered methods with spec key `key`.
std::string methods_with_key(const std::string& key) {
    std::string family, names;
    for (const MethodEntry& e : render_registry().entries())
        if (e.setting_by_spec_key(key)) family = e.family, names += (names.empty() ? "" : ", ") + e.name;
    return "the " + family + " methods (" + names + ")";
}

std::string read_string(const json& v, const std::string& path, const char* what) {
    if (!v.is_string()) fail(path + " must be " + what + ", got " + written(v) + " (" + kind_of(v) + ")");
    return v.get<std::string>();
}

/// Names become file and folder names (the default --out, images/<case>_...png): nothing that
/// could climb out of the output folder, hide, or trouble a shell or a CSV file.
std::string checked_name(const std::string& name, const std::string& path) {
    if (!is_file_name(name))
        fail(path + " is " + written(json(name)) + "; it names files and folders, so use " + kFileNameRule +
             ", e.g. \"small_study\"");
    return name;
}

std::string read_file_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// A value or an array of values, each read by `one`.
template <typename T, typename F>
std::vector<T> read_list(const json& v, const std::string& path, F one) {
    std::vector<T> out;
    if (!v.is_array()) {
        out.push_back(one(v, path));
        return out;
    }
    if (v.empty()) fail(path + " is an empty array; give at least one value");
    for (size_t i = 0; i < v.size(); ++i) out.push_back(one(v[i], path + "[" + std::to_string(i) + "]"));
    return out;
}

/// The registry's settings of one expanded configuration at `where`, read by Registry::from_json
/// (the method's defaults, ranges and cross-setting checks, as the CLI's flags get them): the
/// expanded keys the method takes, a fixed resolution as adaptive_resolution off, and the case's
/// list memory.
MethodSettings settings_of(const StudyMethod& sm, uint32_t list_bytes_per_pixel, const std::string& where) {
    const MethodEntry& entry = *render_registry().find(sm.method);
    json object = json::object();
    const std::pair<const char*, json> expanded[] = {
        {"visual", sm.visual}, {"size", sm.size}, {"recursion", sm.recursion}, {"bisection", sm.bisection}};
    for (const auto& [key, value] : expanded)
        if (entry.setting_by_spec_key(key)) object[key] = value;
    if (sm.resolution != "adaptive") object["adaptive_resolution"] = false;
    if (entry.setting_by_spec_key("surface")) object["surface"] = sm.surface;
    if (list_bytes_per_pixel && entry.setting_by_spec_key("list_bytes_per_pixel"))
        object["list_bytes_per_pixel"] = list_bytes_per_pixel;
    auto settings = render_registry().from_json(sm.method, object, where);
    if (!settings) fail(settings.error());
    // Wu et al. Fig. 5's configurations: the binary density grid alone (section 4.1), or with
    // the skip to D_agg (4.2); a ray per pixel, so that every pixel has its own step count.
    if (sm.stepping != "all") {
        SurfaceSettings* s = settings.value().get<SurfaceSettings>();
        if (!s) fail(where + ".stepping applies to the adaptive method only");
        s->use_mask = true;
        s->use_skip = sm.stepping != "mask";
        s->exact_skip = sm.stepping != "mask_wu_skip";
        s->adaptive_resolution = false;
    }
    return settings.value();
}

std::vector<StudyMethod> read_methods(const json& v, const std::string& path, uint32_t list_bytes_per_pixel) {
    if (!v.is_array() || v.empty())
        fail(path + " must be a non-empty array such as [{\"method\": \"sbuffer\"}, {\"method\": \"adaptive\"}], got " +
             written(v));
    std::vector<StudyMethod> out;
    for (size_t i = 0; i < v.size(); ++i) {
        const std::string where = path + "[" + std::to_string(i) + "]";
        const json& m = v[i];
        if (!m.is_object()) fail(where + " must be an object such as {\"method\": \"sbuffer\"}, got " + written(m));
        check_keys(m, "in " + where, kMethodKeys);
        require(m, "method", "in " + where, "\"method\": \"sbuffer\"");
        const std::string name = read_string(m["method"], child(where, "method"), "a method name");
        const MethodEntry* entry = render_registry().find(name);
        if (!entry) fail(child(where, "method") + " is \"" + name + "\"; use " + render_registry().names());
        const Result<StudyFamily> known = study_family(entry->family);
        if (!known) fail(child(where, "method") + " is \"" + name + "\", " + known.error());
        const StudyFamily family = known.value();
        for (const char* key : {"visual", "size", "recursion", "bisection"})
            if (m.contains(key) && !entry->setting_by_spec_key(key))
                fail(child(where, key) + " applies to " + methods_with_key(key) + " only, not " + name);
        for (const char* key : {"resolution", "stepping"})
            if (m.contains(key) && name != "adaptive")
                fail(child(where, key) + " applies to the adaptive method only, not " + name);
        if (m.contains("surface") && !entry->setting_by_spec_key("surface"))
            fail(child(where, "surface") + " applies to " + methods_with_key("surface") + " only, not " + name);
        if (m.contains("stepping") && m.contains("resolution"))
            fail(child(where, "stepping") +
                 " draws a ray per pixel (full resolution); drop \"resolution\" or give the "
                 "stepping configurations a method entry of their own");
        auto strings = [&](const char* key, std::vector<std::string> fallback, std::set<std::string> allowed) {
            if (!m.contains(key)) return fallback;
            auto list = read_list<std::string>(m[key], child(where, key), [&](const json& x, const std::string& p) {
                std::string s = read_string(x, p, "a string");
                if (!allowed.count(s)) {
                    std::string options;
                    for (const auto& a : allowed) options += (options.empty() ? "" : ", ") + a;
                    fail(p + " is \"" + s + "\"; use one of " + options);
                }
                return s;
            });
            return list;
        };
        auto numbers = [&](const char* key, float fallback, const Range& r) {
            if (!m.contains(key)) return std::vector<float>{fallback};
            return read_list<float>(m[key], child(where, key),
                                    [&](const json& x, const std::string& p) { return read_number(x, p, r); });
        };
        auto integers = [&](const char* key, uint32_t fallback, uint32_t lo, uint32_t hi) {
            if (!m.contains(key)) return std::vector<uint32_t>{fallback};
            return read_list<uint32_t>(m[key], child(where, key),
                                       [&](const json& x, const std::string& p) { return read_integer(x, p, lo, hi); });
        };
        const auto visuals = strings("visual", {"gradient"}, {"gradient", "real"});
        const auto sizes =
            numbers("size", 1.0f, {0.5, 8.0, false, false, "a number of particle spacings from 0.5 to 8"});
        const auto recursions = integers("recursion", 1, 1, 4);
        const auto bisections = integers("bisection", 3, 0, 32);
        const auto resolutions = strings("resolution", {"adaptive"}, {"full", "half", "quarter", "adaptive"});
        const auto steppings = strings("stepping", {"all"}, {"all", "mask", "mask_skip", "mask_wu_skip"});
        const auto surfaces = strings("surface", {"anisotropic"}, {"isotropic", "anisotropic"});
        for (const auto& surface : surfaces)
            for (const auto& visual : visuals)
                for (float size : sizes)
                    for (uint32_t recursion : recursions)
                        for (uint32_t bisection : bisections)
                            for (const auto& resolution : resolutions)
                                for (const auto& stepping : steppings) {
                                    StudyMethod sm;
                                    sm.method = name;
                                    sm.family = family;
                                    sm.visual = visual;
                                    sm.size = size;
                                    sm.recursion = visual == "real" ? recursion : 1;
                                    sm.bisection = bisection;
                                    sm.resolution = resolution;
                                    sm.stepping = stepping;
                                    sm.surface = entry->setting_by_spec_key("surface") ? surface : "anisotropic";
                                    bool seen = false;
                                    for (const auto& o : out) seen = seen || o.label() == sm.label();
                                    if (seen) continue;
                                    sm.settings = settings_of(sm, list_bytes_per_pixel, where);
                                    out.push_back(std::move(sm));
                                }
    }
    return out;
}

StudyCamera read_camera(const json& v, const std::string& path) {
    StudyCamera c;
    if (v.is_string()) {
        c.preset = v.get<std::string>();
        if (c.preset != "front" && c.preset != "far" && c.preset != "closeup")
            fail(path + " is \"" + c.preset +
                 "\"; use front, far (twice the distance), closeup (inside the fluid's reach) "
                 "or {\"eye\": [x, y, z], \"target\": [x, y, z], \"fov\": 40}");
        return c;
    }
    if (!v.is_object()) fail(path + " must be a preset name or {\"eye\": [..], \"target\": [..]}, got " + written(v));
    c.preset = "custom";
    c.custom = read_view_camera(v, path);
    return c;
}

StudyCase read_case(const json& v, const std::string& path, const fs::path& base_dir) {
    if (!v.is_object())
        fail(path + " must be an object with \"name\", \"resolutions\" and \"methods\", got " + written(v));
    check_keys(v, "in " + path, kCaseKeys);
    for (const char* key : {"name", "resolutions", "methods"})
        require(v, key, "in " + path, std::string("\"") + key + "\": ...");
    StudyCase c;
    c.name = checked_name(read_string(v["name"], child(path, "name"), "a name"), child(path, "name"));
    if (v.contains("scene")) {
        c.scene = read_string(v["scene"], child(path, "scene"), "\"dam_break\" or a scene file path");
        if (c.scene != "dam_break") {
            c.scene = (base_dir / c.scene).lexically_normal().string();
            std::error_code ec;
            if (!fs::is_regular_file(c.scene, ec))
                fail(child(path, "scene") + ": no scene file " + c.scene + "; paths are relative to the spec file");
        }
    }
    if (v.contains("particles")) {
        c.particles =
            read_list<uint32_t>(v["particles"], child(path, "particles"),
                                [](const json& x, const std::string& p) { return read_integer(x, p, 64, 64u << 20); });
    } else if (c.scene == "dam_break") {
        c.particles = {4096};
    }
    if (v.contains("time") && !(v["time"].is_string() && v["time"] == "half_tank"))
        c.time_s = read_number(v["time"], child(path, "time"),
                               {0.0, 60.0, false, false, "\"half_tank\" or seconds from 0 to 60"});
    if (v.contains("camera")) c.camera = read_camera(v["camera"], child(path, "camera"));
    c.resolutions = read_list<std::pair<uint32_t, uint32_t>>(
        v["resolutions"], child(path, "resolutions"), [](const json& x, const std::string& p) {
            std::pair<uint32_t, uint32_t> wh;
            if (!x.is_string() || !parse_resolution(x.get<std::string>(), &wh.first, &wh.second))
                fail(p + " must be a resolution such as \"512x512\" (each side " + picture_side_range() + "), got " +
                     written(x));
            return wh;
        });
    if (v.contains("list_bytes_per_pixel"))
        c.list_bytes_per_pixel =
            read_integer(v["list_bytes_per_pixel"], child(path, "list_bytes_per_pixel"), 8, 1u << 16);
    c.methods = read_methods(v["methods"], child(path, "methods"), c.list_bytes_per_pixel);
    if (v.contains("note")) c.note = read_string(v["note"], child(path, "note"), "a sentence");
    return c;
}

SolverMapSpec read_map(const json& v, const std::string& path, const fs::path& base_dir) {
    if (!v.is_object()) fail(path + " must be an object with \"scene\", \"dt\" and \"iterations\", got " + written(v));
    check_keys(v, "in " + path, kMapKeys);
    for (const char* key : {"scene", "dt", "iterations"})
        require(v, key, "in " + path, std::string("\"") + key + "\": ...");
    SolverMapSpec m;
    m.scene = (base_dir / read_string(v["scene"], child(path, "scene"), "a scene file path")).lexically_normal();
    std::error_code ec;
    if (!fs::is_regular_file(m.scene, ec))
        fail(child(path, "scene") + ": no scene file " + m.scene.string() + "; paths are relative to the spec file");
    m.frame_dts = read_list<float>(v["dt"], child(path, "dt"), [](const json& x, const std::string& p) {
        return read_number(
            x, p, {0.0, kMaxFrameDt, true, false, "a time step in seconds, above 0 and at most " + fmt(kMaxFrameDt)});
    });
    m.iterations =
        read_list<uint32_t>(v["iterations"], child(path, "iterations"),
                            [](const json& x, const std::string& p) { return read_integer(x, p, 1, kMaxIterations); });
    if (v.contains("control_pressure"))
        m.control_pressures = read_list<float>(
            v["control_pressure"], child(path, "control_pressure"), [](const json& x, const std::string& p) {
                return read_number(x, p, {0.0, 1e9, true, false, "a pressure in pascals above 0"});
            });
    if (v.contains("time"))
        m.sim_time_s =
            read_number(v["time"], child(path, "time"), {0.0, 60.0, true, false, "seconds above 0, at most 60"});
    return m;
}

}  // namespace

Result<StudyFamily> study_family(const std::string& family) {
    if (family == "surface") return StudyFamily::surface;
    if (family == "metaball") return StudyFamily::metaball;
    if (family == "screen_space") return StudyFamily::screen_space;
    return Error{"a method of the family \"" + family +
                 "\", which a study cannot measure (it knows surface, "
                 "metaball and screen_space); use a method of those families (aquaform help lists them)"};
}

std::string StudyMethod::label() const {
    std::ostringstream text;
    text << method;
    if (family == StudyFamily::metaball) {
        text << " " << visual;
        text << " x" << size;
        if (visual == "real") text << " r" << recursion;
        text << " b" << bisection;
    }
    if (method == "adaptive" && resolution != "adaptive") text << " " << resolution;
    if (stepping == "mask") text << " mask";
    if (stepping == "mask_skip") text << " mask+skip";
    if (stepping == "mask_wu_skip") text << " mask+wu-skip";
    if (surface == "isotropic") text << " iso";
    return text.str();
}

uint32_t StudyMethod::resolution_divisor() const { return resolution == "half" ? 2 : resolution == "quarter" ? 4 : 1; }

Result<StudySpec> parse_study_spec(const std::string& text, const std::string& origin, const fs::path& base_dir) {
    try {
        const json j = parse_strict(text, origin);
        if (!j.is_object())
            fail("the top level must be an object {\"name\": ..., \"cases\": [...]}, got " + written(j));
        check_keys(j, "at top level", kTopKeys);
        require(j, "cases", "at top level",
                "\"cases\": [{\"name\": \"small\", \"resolutions\": [\"256x256\"], \"methods\": [...]}]");
        StudySpec spec;
        spec.name = j.contains("name")
                        ? checked_name(read_string(j["name"], "name", "a name"), "name")
                        : checked_name(fs::path(origin).stem().string(), "name (none given, so the file's name)");
        if (j.contains("repeats")) spec.repeats = read_integer(j["repeats"], "repeats", 1, 20);
        if (!j["cases"].is_array() || j["cases"].empty())
            fail("cases must be a non-empty array of cases, got " + written(j["cases"]));
        std::set<std::string> names;
        for (size_t i = 0; i < j["cases"].size(); ++i) {
            spec.cases.push_back(read_case(j["cases"][i], "cases[" + std::to_string(i) + "]", base_dir));
            if (!names.insert(spec.cases.back().name).second)
                fail("cases[" + std::to_string(i) + "].name \"" + spec.cases.back().name +
                     "\" is used twice; names label the rows");
        }
        if (j.contains("solver_map")) {
            const json& maps = j["solver_map"];
            if (maps.is_array()) {
                for (size_t i = 0; i < maps.size(); ++i)
                    spec.solver_maps.push_back(read_map(maps[i], "solver_map[" + std::to_string(i) + "]", base_dir));
            } else {
                spec.solver_maps.push_back(read_map(maps, "solver_map", base_dir));
            }
        }
        spec.identity = j.dump();
        for (const StudyCase& c : spec.cases)
            if (c.scene != "dam_break")
                spec.identity += "\n" + read_file_text(c.scene);  // contents: any working directory
        for (const SolverMapSpec& m : spec.solver_maps) spec.identity += "\n" + read_file_text(m.scene);
        return spec;
    } catch (const Invalid& e) {
        return Error{e.has_origin ? e.message : origin + ": " + e.message};
    } catch (const std::exception& e) {
        return Error{origin + ": " + std::string(e.what())};
    }
}

Result<bool> set_particle_count(StudySpec& spec, uint64_t particles) {
    for (StudyCase& c : spec.cases) {
        if (c.scene == "dam_break") {  // sized by its count (bench/bench_scenes.h)
            c.particles = {uint32_t(particles)};
            continue;
        }
        auto loaded = load_scene(c.scene);
        if (!loaded) return Error{loaded.error()};
        auto sized = scaled_scene(loaded.value(), particles);
        if (!sized) return Error{"case " + c.name + ": " + sized.error()};
        c.particles = {uint32_t(particles)};
    }
    spec.identity += "\n--particles " + std::to_string(particles);
    return true;
}

std::string spec_hash(const StudySpec& spec) {
    uint64_t h = 14695981039346656037ull;  // FNV-1a
    for (unsigned char c : spec.identity) h = (h ^ c) * 1099511628211ull;
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", (unsigned long long)h);
    return text;
}

std::vector<std::optional<uint32_t>> study_frame_counts(const StudyCase& c) {
    std::vector<std::optional<uint32_t>> counts(c.particles.begin(), c.particles.end());
    if (counts.empty()) counts.push_back(std::nullopt);  // a scene file at its own count
    return counts;
}

std::string study_frame_key(const StudyCase& c, std::optional<uint32_t> particles) {
    return c.name + "/" + (particles ? std::to_string(*particles) : std::string("scene"));
}

std::string study_cell_key(const std::string& frame_key, uint32_t width, uint32_t height, const std::string& label) {
    return frame_key + "/" + std::to_string(width) + "x" + std::to_string(height) + "/" + label;
}

std::vector<std::string> study_cell_keys(const StudySpec& spec) {
    std::vector<std::string> keys;
    for (const StudyCase& c : spec.cases)
        for (const auto& n : study_frame_counts(c))
            for (const auto& [w, h] : c.resolutions)
                for (const StudyMethod& m : c.methods)
                    keys.push_back(study_cell_key(study_frame_key(c, n), w, h, m.label()));
    return keys;
}

Result<bool> check_study_scenes(const StudySpec& spec) {
    for (size_t i = 0; i < spec.cases.size(); ++i) {
        const StudyCase& c = spec.cases[i];
        if (c.scene == "dam_break") continue;
        const std::string where = "cases[" + std::to_string(i) + "] (" + c.name + "): ";
        auto loaded = load_scene(c.scene);
        if (!loaded) return Error{where + loaded.error()};
        for (uint32_t n : c.particles)
            if (auto sized = scaled_scene(loaded.value(), n); !sized)
                return Error{where + "particles " + std::to_string(n) + ": " + sized.error()};
    }
    for (size_t i = 0; i < spec.solver_maps.size(); ++i)
        if (auto ok = check_solver_map(spec.solver_maps[i]); !ok)
            return Error{(spec.solver_maps.size() > 1 ? "solver_map[" + std::to_string(i) + "]: " : "solver_map: ") +
                         ok.error()};
    return true;
}

Result<StudySpec> load_study_spec(const fs::path& path) {
    try {
        const std::string text = read_json_file(path, "study spec", "check the path (specs live in assets/studies/)");
        return parse_study_spec(text, path.string(), path.parent_path());
    } catch (const Invalid& e) {
        return Error{e.message};
    }
}

}  // namespace aquaform::study
