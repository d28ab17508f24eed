// Strict JSON field readers shared by aquaform's file formats (scene files and their control
// section). Readers throw Invalid; the loader catches it and prefixes the file name, so every
// message names the file, the key path, the value as written and the fix.
#pragma once

#include <cstdint>
#include <filesystem>
#include <limits>
#include <span>
#include <string>
#include <string_view>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "core/box.h"
#include "core/camera.h"

namespace aquaform::json_fields {

using json = nlohmann::json;

struct Invalid {
    std::string message;
    bool has_origin = false;  ///< the message already starts with the file name
};

[[noreturn]] void fail(std::string message);

/// The value as the file wrote it (re-serialised compactly, long values shortened).
std::string written(const json& v);
/// "a string", "an array of 3 elements", ...: what the file gave instead.
std::string kind_of(const json& v);
std::string fmt(double x);
std::string fmt(const glm::vec3& v);
std::string fmt(const Box& b);
std::string join(std::span<const std::string_view> keys);
/// "a", "b", "c": names as a message lists them (empty for none).
std::string quoted_list(std::span<const std::string> names);

/// `where` is "at top level" or "in <path>". Rejects keys outside `allowed`, suggesting the
/// closest allowed key for a typo.
void check_keys(const json& obj, const std::string& where, std::span<const std::string_view> allowed);
void require(const json& obj, std::string_view key, const std::string& where, const std::string& example);
/// "parent.key" (or "key" at top level).
std::string child(const std::string& parent, std::string_view key);

/// A closed or open interval with the phrase that tells the user what to write.
struct Range {
    double lo = -std::numeric_limits<double>::infinity();
    double hi = std::numeric_limits<double>::infinity();
    bool lo_open = false;
    bool hi_open = false;
    std::string what = "a number";

    bool contains(double x) const {
        return (lo_open ? x > lo : x >= lo) && (hi_open ? x < hi : x <= hi) && std::isfinite(x);
    }
};

float read_number(const json& v, const std::string& path, const Range& r);
uint32_t read_integer(const json& v, const std::string& path, uint32_t lo, uint32_t hi);
glm::vec3 read_vec3(const json& v, const std::string& path, const char* what);
/// Reads {"min": [..], "max": [..]} and checks max > min on every axis.
Box read_box(const json& v, const std::string& path, const std::string& example);

/// Reads {"eye": [..], "target": [..], "fov": degrees (optional)}: a camera placed by hand.
ViewCamera read_view_camera(const json& v, const std::string& path);

/// Refuses an array `v` of more than `max` elements, naming `path` and the `fix` (an array of
/// boxes the solver holds in a fixed table, lists that are checked pairwise).
void check_count(const json& v, const std::string& path, size_t max, const std::string& fix);

/// Reads an object of named entries ({"H1": {...}, "H2": {...}}) at `path`, read(name, entry,
/// path.name) each; refuses anything else (naming `example`) and more than `max` entries (naming
/// the `fix`).
template <typename Read>
void read_named(const json& v, const std::string& path, size_t max, const std::string& example, const std::string& fix,
                Read read) {
    if (!v.is_object()) fail(path + " must be an object of named entries, e.g. " + example + ", got " + written(v));
    if (v.size() > max)
        fail(path + " has " + std::to_string(v.size()) + " entries; at most " + std::to_string(max) + " " + fix);
    for (const auto& [name, entry] : v.items()) read(name, entry, path + "." + name);
}

/// The most any aquaform JSON file may hold; parse_strict refuses more (see check_shape).
constexpr size_t kMaxJsonBytes = size_t(16) << 20;
constexpr size_t kMaxJsonDepth = 64;
constexpr size_t kMaxJsonElements = 100000;
/// Throws Invalid (with `origin`) for a file over kMaxJsonBytes; loaders call it before reading.
void check_json_size(uintmax_t bytes, const std::string& origin);
/// The text of the JSON file at `path`. Throws Invalid (starting with the path) when it is not a
/// regular file (a folder, a device such as /dev/zero), is over kMaxJsonBytes or cannot be read:
/// "cannot open <what> "<path>"...; <hint>".
std::string read_json_file(const std::filesystem::path& path, const std::string& what, const std::string& hint);

/// Parses JSON text, refusing duplicate keys and files over the limits above. Syntax errors
/// throw Invalid with `origin`, the line and column, and what to look for.
json parse_strict(const std::string& text, const std::string& origin);

}  // namespace aquaform::json_fields
