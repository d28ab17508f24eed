// Seeded mutations of a JSON document for the fuzz tests: every value's path, and one mutation at
// a path (types, extremes, nesting, deletion, unknown keys, raw text that is not JSON, truncation).
#pragma once

#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace aquaform::json_mutations {

using json = nlohmann::json;

/// Every value's path in `v`, depth first (the root excluded).
inline void collect_paths(const json& v, const json::json_pointer& at, std::vector<json::json_pointer>& out) {
    if (v.is_object())
        for (const auto& [key, child] : v.items()) out.push_back(at / key), collect_paths(child, at / key, out);
    if (v.is_array())
        for (size_t i = 0; i < v.size(); ++i) out.push_back(at / i), collect_paths(v[i], at / i, out);
}

/// The object keys along `path` ("control", "meshes", "ball", ...): a refusal must name one.
inline std::vector<std::string> keys_on(const json::json_pointer& path) {
    std::vector<std::string> keys;
    for (json::json_pointer p = path; !p.empty(); p = p.parent_pointer())
        if (p.back().find_first_not_of("0123456789") != std::string::npos) keys.push_back(p.back());
    return keys;
}

struct Mutation {
    std::string text;
    json::json_pointer path;
    bool syntax = false;  ///< not JSON any more: the message names a line instead of a key
};

/// One mutation of `scene` at `path`, drawn from `random`.
inline Mutation mutate(const json& scene, const json::json_pointer& path, std::mt19937& random) {
    const auto pick = [&](size_t n) { return std::uniform_int_distribution<size_t>(0, n - 1)(random); };
    json deep = json::array();
    for (int i = 0; i < 80; ++i) deep = json::array({deep});
    const json values[] = {nullptr,
                           true,
                           "text",
                           -1,
                           0,
                           1e308,
                           -1e308,
                           1e-320,
                           4294967296.0,
                           18446744073709551615ull,
                           json::array(),
                           json::object(),
                           deep,
                           std::string(100000, 'x'),
                           json::array({1, 2}),
                           json::object({{"x", 1}}),
                           -0.0,
                           2.5,
                           1e6,
                           json::array({0, 0, 0})};
    const char* raw[] = {"NaN", "Infinity", "1e400", "-", "[", "}", "0x10", "'x'", "tru"};
    json j = scene;
    Mutation m{"", path, false};
    switch (pick(5)) {
        case 0:
        case 1:
            j[path] = values[pick(std::size(values))];
            break;
        case 2:  // delete, or (under an object) an unknown key beside it
            if (j[path.parent_pointer()].is_object()) {
                if (pick(2))
                    j[path.parent_pointer()].erase(path.back());
                else
                    j[path.parent_pointer()][path.back() + "_typo"] = 1;
            } else {
                j[path.parent_pointer()].erase(std::stoul(path.back()));
            }
            break;
        case 3:  // raw text that is not JSON where the value was
            j[path] = "@@placeholder@@";
            m.text = j.dump(2);
            m.text.replace(m.text.find("\"@@placeholder@@\""), 17, raw[pick(std::size(raw))]);
            m.syntax = true;
            return m;
        case 4:  // the file cut short
            m.text = j.dump(2);
            m.text.resize(pick(m.text.size()));
            m.syntax = true;
            return m;
    }
    m.text = j.dump(2);
    return m;
}

/// Whether a refusal of `m` is a good one: one line, starting with `origin`, naming a key on the
/// mutated path (or the line of a syntax error). Empty when it is, else what is wrong.
inline std::string judge_refusal(const Mutation& m, const std::string& origin, const std::string& error) {
    if (error.rfind(origin + ": ", 0) != 0) return "does not start with the file";
    if (error.find('\n') != std::string::npos) return "is more than one line";
    for (const std::string& key : keys_on(m.path))
        if (error.find(key) != std::string::npos) return "";
    if (m.syntax && error.find("line ") != std::string::npos) return "";
    return "names no key on the path " + m.path.to_string();
}

}  // namespace aquaform::json_mutations
