#include "render/registry.h"

#include <cstdio>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "core/number_text.h"
#include "render/picture_size.h"

namespace aquaform {

namespace {

std::string format_number(double v) {
    std::ostringstream text;
    text << v;
    return text.str();
}

bool is_switch(SettingType t) { return t == SettingType::off_switch || t == SettingType::on_switch; }

/// The methods (of other families) that take `flag`.
std::string methods_with_flag(const Registry& registry, const std::string& flag) {
    std::string out;
    for (const MethodEntry& e : registry.entries())
        if (e.setting_by_flag(flag)) out += (out.empty() ? "" : ", ") + e.name;
    return out;
}

/// The setting's range in words, with the bounds checked where the words do not give both.
std::string range_text(const SettingSpec& s) {
    if (s.type != SettingType::number && s.type != SettingType::integer) return s.range;
    const std::string lo = format_number(s.min), hi = format_number(s.max);
    if (s.range.find(lo) != std::string::npos && s.range.find(hi) != std::string::npos) return s.range;
    return s.range + " (" + lo + " to " + hi + ")";
}

/// Checks `v` against the setting's range; the message names `name` (a flag or a spec path).
Result<bool> in_range(const SettingSpec& s, double v, const std::string& name) {
    if (s.type != SettingType::number && s.type != SettingType::integer) return true;
    if (std::isfinite(v) && v >= s.min && v <= s.max) return true;
    return Error{name + " = " + format_number(v) + " is out of range for render setting " + s.key + "; use " +
                 range_text(s)};
}

Result<bool> finish(const MethodEntry& entry, const MethodSettings& settings) {
    return entry.validate ? entry.validate(settings) : Result<bool>(true);
}

}  // namespace

std::string RenderStats::describe() const {
    std::ostringstream text;
    text << rays << " rays";
    if (rays) text << ", " << double(evaluations) / double(rays) << " evaluations per ray";
    if (cut)
        text << "; " << cut << " " << cut_unit
             << " CUT SHORT by the device's loop limit (their surface may be missing)";
    if (list_overflow) text << "; lists OVERFLOWED (need " << list_bytes_needed << " bytes)";
    if (dropped_particles) text << "; " << dropped_particles << " particles at the eye plane in no list";
    if (!family_line.empty()) text << " [" << family_line << "]";
    if (!resolution_note.empty()) text << " (" << resolution_note << ")";
    return text.str();
}

void Renderer::configure(const MethodSettings& settings) {
    check(settings);
    settings_ = settings;
}

std::string SettingSpec::default_text(const MethodSettings& defaults) const {
    const double v = get(defaults);
    switch (type) {
        case SettingType::choice:
            return choices.at(size_t(v));
        case SettingType::off_switch:
        case SettingType::on_switch:
            return v != 0.0 ? "on" : "off";
        default:
            return format_number(v);
    }
}

const SettingSpec* MethodEntry::setting_by_flag(const std::string& flag) const {
    for (const SettingSpec& s : settings)
        if (!s.flag.empty() && s.flag == flag) return &s;
    return nullptr;
}

const SettingSpec* MethodEntry::setting_by_spec_key(const std::string& key) const {
    for (const SettingSpec& s : settings)
        if (!s.spec_key.empty() && s.spec_key == key) return &s;
    return nullptr;
}

const MethodEntry* Registry::find(const std::string& name) const {
    for (const MethodEntry& e : entries_)
        if (e.name == name) return &e;
    return nullptr;
}

std::string Registry::names() const {
    std::string out;
    for (size_t i = 0; i < entries_.size(); ++i)
        out += (i == 0 ? "" : i + 1 == entries_.size() ? " or " : ", ") + entries_[i].name;
    return out;
}

Result<const MethodEntry*> Registry::lookup(const std::string& name) const {
    if (const MethodEntry* e = find(name)) return e;
    return Error{"unknown render method '" + name + "'; use " + names() + " (aquaform help describes each)"};
}

std::unique_ptr<Renderer> Registry::create(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width,
                                           uint32_t height, uint32_t max_particles,
                                           const MethodSettings& settings) const {
    auto entry = lookup(settings.method());
    if (!entry) throw Failure(entry.error());
    if (auto valid = finish(*entry.value(), settings); !valid) throw Failure(valid.error());
    return entry.value()->make(ctx, domain, width, height, max_particles, settings);
}

Result<MethodSettings> Registry::from_flags(const std::string& method,
                                            const std::map<std::string, std::string>& flags) const {
    auto found = lookup(method);
    if (!found) return Error{found.error()};
    const MethodEntry& entry = *found.value();
    MethodSettings settings = entry.defaults;
    for (const auto& [flag, text] : flags) {
        const SettingSpec* s = entry.setting_by_flag(flag);
        if (!s) {
            const std::string others = methods_with_flag(*this, flag);
            if (!others.empty()) return Error{flag + " applies to the methods " + others + ", not to " + method};
            continue;
        }
        double v = 0.0;
        if (is_switch(s->type)) {
            v = s->type == SettingType::on_switch ? 1.0 : 0.0;
        } else if (s->type == SettingType::choice) {
            auto it = std::find(s->choices.begin(), s->choices.end(), text);
            if (it == s->choices.end()) {
                std::string options;
                for (const auto& c : s->choices) options += (options.empty() ? "" : ", ") + c;
                return Error{flag + " must be one of " + options + ", got \"" + text + "\""};
            }
            v = double(it - s->choices.begin());
        } else {
            // Strict: the whole text is the value, so nothing wraps or is read in part.
            const bool number = s->type == SettingType::number;
            std::optional<double> parsed = number_text::finite_number(text);
            if (!number) {
                const std::optional<uint64_t> whole = number_text::whole_number(text);
                parsed = whole ? std::optional<double>(double(*whole)) : std::nullopt;
            }
            if (!parsed)
                return Error{flag + " must be " + (number ? "a number" : "a whole number") + " (render setting " +
                             s->key + ": " + range_text(*s) + "), got \"" + text + "\""};
            if (!in_range(*s, *parsed, flag))  // said with the value as typed, every digit kept
                return Error{flag + " = " + text + " is out of range for render setting " + s->key + "; use " +
                             range_text(*s)};
            v = *parsed;
        }
        s->set(settings, v);
    }
    if (auto valid = finish(entry, settings); !valid) return Error{valid.error()};
    return settings;
}

Result<MethodSettings> Registry::from_json(const std::string& method, const nlohmann::json& object,
                                           const std::string& path) const {
    auto found = lookup(method);
    if (!found) return Error{found.error()};
    const MethodEntry& entry = *found.value();
    MethodSettings settings = entry.defaults;
    for (const SettingSpec& s : entry.settings) {
        if (s.spec_key.empty() || !object.contains(s.spec_key)) continue;
        const nlohmann::json& v = object[s.spec_key];
        const std::string where = path + "." + s.spec_key;
        double x = 0.0;
        if (is_switch(s.type)) {
            if (!v.is_boolean()) return Error{where + " must be true or false, got " + v.dump()};
            x = v.get<bool>() ? 1.0 : 0.0;
        } else if (s.type == SettingType::choice) {
            auto it =
                v.is_string() ? std::find(s.choices.begin(), s.choices.end(), v.get<std::string>()) : s.choices.end();
            if (it == s.choices.end()) {
                std::string options;
                for (const auto& c : s.choices) options += (options.empty() ? "" : ", ") + c;
                return Error{where + " is " + v.dump() + "; use one of " + options};
            }
            x = double(it - s.choices.begin());
        } else {
            if (!v.is_number() || (s.type == SettingType::integer && !v.is_number_integer()))
                return Error{where + " must be " + (s.type == SettingType::integer ? "an integer" : "a number") + " (" +
                             s.range + "), got " + v.dump()};
            x = v.get<double>();
            if (auto ok = in_range(s, x, where); !ok) return Error{ok.error()};
        }
        s.set(settings, x);
    }
    if (auto valid = finish(entry, settings); !valid) return Error{path + ": " + valid.error()};
    return settings;
}

std::vector<std::string> Registry::value_flags() const {
    std::vector<std::string> out;
    for (const MethodEntry& e : entries_)
        for (const SettingSpec& s : e.settings)
            if (!s.flag.empty() && !is_switch(s.type) && std::find(out.begin(), out.end(), s.flag) == out.end())
                out.push_back(s.flag);
    return out;
}

std::vector<std::string> Registry::switch_flags() const {
    std::vector<std::string> out;
    for (const MethodEntry& e : entries_)
        for (const SettingSpec& s : e.settings)
            if (!s.flag.empty() && is_switch(s.type) && std::find(out.begin(), out.end(), s.flag) == out.end())
                out.push_back(s.flag);
    return out;
}

std::string Registry::usage() const {
    std::ostringstream text;
    text << "        methods:\n";
    for (const MethodEntry& e : entries_) {
        text << "          " << e.name << std::string(e.name.size() < 15 ? 15 - e.name.size() : 1, ' ') << e.description
             << "\n";
    }
    // Each family's flags, every flag once.
    std::vector<std::string> families;
    for (const MethodEntry& e : entries_) {
        if (std::find(families.begin(), families.end(), e.family) != families.end()) continue;
        families.push_back(e.family);
        std::string members;
        for (const MethodEntry& m : entries_)
            if (m.family == e.family) members += (members.empty() ? "" : ", ") + m.name;
        text << "        flags of " << members << ":\n";
        std::vector<std::string> printed;  // a flag once per family, with its first member's default
        for (const MethodEntry& m : entries_) {
            if (m.family != e.family) continue;
            for (const SettingSpec& s : m.settings) {
                if (s.flag.empty() || std::find(printed.begin(), printed.end(), s.flag) != printed.end()) continue;
                printed.push_back(s.flag);
                std::string flag = s.flag;
                if (s.type == SettingType::choice) {
                    flag += " ";
                    for (size_t i = 0; i < s.choices.size(); ++i) flag += (i ? "|" : "") + s.choices[i];
                } else if (!is_switch(s.type)) {
                    flag += " V";
                }
                text << "          " << flag << std::string(flag.size() < 26 ? 26 - flag.size() : 1, ' ') << s.help;
                if (!is_switch(s.type))
                    text << " (default " << s.default_text(m.defaults) << (s.range.empty() ? "" : "; " + s.range)
                         << ")";
                text << "\n";
            }
        }
    }
    return text.str();
}

const Registry& render_registry() {
    static const Registry registry = [] {
        Registry r;
        register_surface_methods(r);
        register_metaball_methods(r);
        register_screen_space_methods(r);
        return r;
    }();
    return registry;
}

bool parse_resolution(const std::string& text, uint32_t* w, uint32_t* h) {
    // Digits, 'x', digits and nothing else (sscanf took " 640x480junk" and wrapped 4294967296).
    const size_t x = text.find_first_of("xX");
    if (x == std::string::npos) return false;
    const std::optional<uint64_t> a = number_text::whole_number(std::string_view(text).substr(0, x));
    const std::optional<uint64_t> b = number_text::whole_number(std::string_view(text).substr(x + 1));
    if (!a || !b || !picture_size_ok(*a, *b)) return false;
    *w = uint32_t(*a);
    *h = uint32_t(*b);
    return true;
}

}  // namespace aquaform
