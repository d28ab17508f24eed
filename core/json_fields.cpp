// Strict JSON field readers shared by every file format of aquaform (scenes, control sections):
// each failure throws Invalid with a message naming the key path, the value and the fix.
#include "core/json_fields.h"

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <limits>
#include <optional>
#include <set>
#include <vector>

namespace aquaform::json_fields {

void fail(std::string message) { throw Invalid{std::move(message)}; }

constexpr std::string_view kBoxKeys[] = {"min", "max"};
constexpr const char* kAxis[] = {"x", "y", "z"};

// ---- formatting ------------------------------------------------------------------------------

/// The value as the file wrote it (re-serialised compactly, long values shortened).
std::string written(const json& v) {
    std::string s = v.dump();
    if (s.size() > 60) s = s.substr(0, 57) + "...";
    return s;
}

std::string kind_of(const json& v) {
    switch (v.type()) {
        case json::value_t::null:
            return "null";
        case json::value_t::boolean:
            return "a boolean";
        case json::value_t::string:
            return "a string";
        case json::value_t::object:
            return "an object";
        case json::value_t::array:
            return "an array of " + std::to_string(v.size()) + " elements";
        default:
            return "a number";
    }
}

std::string fmt(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", x);
    // "1e-5", as a user writes it and the docs quote it, not printf's "1e-05".
    std::string s = buf;
    if (size_t e = s.find("e-0"); e != std::string::npos) s.erase(e + 2, 1);
    if (size_t e = s.find("e+0"); e != std::string::npos) s.erase(e + 2, 1);
    return s;
}

std::string fmt(const glm::vec3& v) {
    std::string s = "[";  // appended, not "[" + ..., which trips a GCC 12 -Wrestrict false positive
    s += fmt(v.x) + "," + fmt(v.y) + "," + fmt(v.z) + "]";
    return s;
}

std::string fmt(const Box& b) { return fmt(b.min) + ".." + fmt(b.max); }

std::string join(std::span<const std::string_view> keys) {
    std::string s;
    for (auto k : keys) s += (s.empty() ? "" : ", ") + std::string(k);
    return s;
}

std::string quoted_list(std::span<const std::string> names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "\"" : ", \"") + n + "\"";
    return s;
}

// ---- keys ------------------------------------------------------------------------------------

namespace {

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

}  // namespace

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

float read_number(const json& v, const std::string& path, const Range& r) {
    if (!v.is_number()) fail(path + " must be " + r.what + ", got " + written(v) + " (" + kind_of(v) + ")");
    double d = v.get<double>();
    if (!r.contains(d)) fail(path + " is " + written(v) + "; it must be " + r.what);
    // The decimal as written is what the range judges (0.1 is within "at most 0.1" although
    // float(0.1) is a hair above it); the float only has to hold it: no overflow, no underflow
    // of a non-zero value to zero or to the denormals, which lose its precision.
    float f = static_cast<float>(d);
    if (std::isinf(f) || (d != 0.0 && std::fabs(f) < FLT_MIN))
        fail(path + " is " + written(v) +
             ", which a 32-bit float cannot hold; use a value between about 1e-30 "
             "and 1e30 (it must be " +
             r.what + ")");
    return f;
}

void check_count(const json& v, const std::string& path, size_t max, const std::string& fix) {
    if (v.is_array() && v.size() > max)
        fail(path + " has " + std::to_string(v.size()) + " elements; at most " + std::to_string(max) +
             " are allowed: " + fix);
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

ViewCamera read_view_camera(const json& v, const std::string& path) {
    static constexpr std::string_view kCameraKeys[] = {"eye", "target", "fov"};
    if (!v.is_object())
        fail(path + " must be an object {\"eye\": [x, y, z], \"target\": [x, y, z], \"fov\": 40}, got " + written(v) +
             " (" + kind_of(v) + ")");
    check_keys(v, "in " + path, kCameraKeys);
    require(v, "eye", "in " + path, "\"eye\": [0.5, 0.4, 1.2]");
    require(v, "target", "in " + path, "\"target\": [0.2, 0.1, 0.1]");
    ViewCamera c;
    c.eye = read_vec3(v["eye"], child(path, "eye"), "an array of three numbers [x, y, z] in metres");
    c.target = read_vec3(v["target"], child(path, "target"), "an array of three numbers [x, y, z] in metres");
    if (v.contains("fov"))
        c.fov_y_degrees =
            read_number(v["fov"], child(path, "fov"), {1.0, 170.0, false, false, "degrees from 1 to 170"});
    if (!(glm::length(c.eye - c.target) > 0.0f)) fail(path + ": eye and target coincide; move the eye away");
    return c;
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

namespace {
/// "20 MiB", or the exact count where MiB would make a size and its limit look equal
/// (16 MiB + 1 byte against 16 MiB).
std::string describe_bytes(uintmax_t bytes, uintmax_t other) {
    return (bytes >> 20) == (other >> 20) ? std::to_string(bytes) + " bytes" : std::to_string(bytes >> 20) + " MiB";
}
}  // namespace

void check_json_size(uintmax_t bytes, const std::string& origin) {
    if (bytes > kMaxJsonBytes)
        throw Invalid{
            origin + ": the file is " + describe_bytes(bytes, kMaxJsonBytes) +
                "; aquaform reads JSON files of "
                "at most " +
                describe_bytes(kMaxJsonBytes, bytes) +
                " (a scene, spec or script is a few KiB): "
                "check that this is the file you meant, and describe large data (meshes, animations) in files of "
                "their own",
            true};
}

std::string read_json_file(const std::filesystem::path& path, const std::string& what, const std::string& hint) {
    std::error_code ec;
    const std::string name = what + " \"" + path.string() + "\"";
    if (!std::filesystem::is_regular_file(path, ec))
        throw Invalid{"cannot open " + name +
                          (std::filesystem::is_directory(path, ec) ? " (it is a folder)"
                           : std::filesystem::exists(path, ec)     ? " (it is not a regular file)"
                                                                   : "") +
                          "; " + hint,
                      true};
    check_json_size(std::filesystem::file_size(path, ec), path.string());
    std::ifstream in(path, std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!in && !in.eof()) throw Invalid{"cannot read " + name + "; check that it is readable", true};
    return text;
}

namespace {

/// Refuses text that no aquaform file needs and that would cost a parser or a reader dearly:
/// files over kMaxJsonBytes, nesting deeper than kMaxJsonDepth (the value echo in messages and
/// the readers recurse) and arrays or objects over kMaxJsonElements (some checks are pairwise).
/// A scan of the raw text, before parsing, so the limit holds whatever the file holds. It also
/// finds the first key written twice in one object (legal JSON, but nlohmann keeps the last, and
/// two "particle_spacing" entries are a mistake): returned as a message for after the parse, so
/// that a syntax error is reported first. (nlohmann's own parse events could find it, but its
/// callback parser takes time quadratic in the file: 5.5 s for a 4.7 MB scene.)
std::optional<std::string> check_shape(const std::string& text, const std::string& origin) {
    check_json_size(text.size(), origin);
    struct Level {
        bool object;
        size_t elements = 0;  // commas seen
        std::string key;      // the object's current key
        std::set<std::string> keys;
    };
    std::optional<std::string> duplicate;
    std::vector<Level> open;
    // "static_boxes[0][0]...": where the scan is, so the refusal names the key as well as the line.
    auto path = [&] {
        std::string p;
        for (size_t i = 0; i < open.size() && i < 8; ++i) {
            if (open[i].object && !open[i].key.empty()) p += (p.empty() ? "" : ".") + open[i].key;
            if (!open[i].object && i + 1 < open.size()) p += "[" + std::to_string(open[i].elements) + "]";
        }
        return (p.empty() ? std::string("the top level") : p) + (open.size() > 8 ? "..." : "");
    };
    auto refuse = [&](size_t line, const std::string& what) {
        throw Invalid{origin + ": line " + std::to_string(line) + ": " + path() + ": " + what, true};
    };
    size_t line = 1;
    bool in_string = false, escaped = false;
    std::string last_string;
    for (size_t at = 0; at < text.size(); ++at) {
        const char c = text[at];
        if (c == '\n') ++line;
        if (in_string) {
            if (escaped) {
                escaped = false;
                // A NUL ends a C string: a path or a name holding one would name another file.
                if (c == 'u' && text.compare(at + 1, 4, "0000") == 0)
                    refuse(line,
                           "a string holds \\u0000 (a NUL character), which would cut a file name or path "
                           "short and name another file; remove it");
            } else if (c == '\\')
                escaped = true;
            else if (c == '"')
                in_string = false;
            else if (last_string.size() < 4096)
                last_string += c;  // longer keys compare by this prefix
            continue;
        }
        if (c == '"') in_string = true, last_string.clear();
        if (c == ':' && !open.empty() && open.back().object) {
            open.back().key = last_string;
            if (!open.back().keys.insert(last_string).second && !duplicate)
                duplicate = origin + ": line " + std::to_string(line) + ": " + path() + ": duplicate key \"" +
                            last_string +
                            "\" (written twice in the same object, and only the last would count); keep one of them";
        }
        if (c == '[' || c == '{') {
            if (open.size() == kMaxJsonDepth)
                refuse(line, "arrays and objects nested more than " + std::to_string(kMaxJsonDepth) +
                                 " levels deep; aquaform's files nest a few levels: remove the extra brackets");
            open.push_back({c == '{'});
        }
        if ((c == ']' || c == '}') && !open.empty()) open.pop_back();
        if (c == ',' && !open.empty() && ++open.back().elements >= kMaxJsonElements)
            refuse(line, "an array or object with more than " + std::to_string(kMaxJsonElements) +
                             " elements; no key of aquaform's files takes that many: check the file, or split "
                             "the data into files of their own");
    }
    return duplicate;
}

}  // namespace

json parse_strict(const std::string& text, const std::string& origin) {
    const std::optional<std::string> duplicate = check_shape(text, origin);
    try {
        json j = json::parse(text);
        if (duplicate) throw Invalid{*duplicate, true};
        return j;
    } catch (const json::parse_error& e) {
        throw Invalid{syntax_error(e, origin), true};
    } catch (const json::out_of_range& e) {
        throw Invalid{number_overflow(e, text, origin), true};
    }
}

}  // namespace aquaform::json_fields
