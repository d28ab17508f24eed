// The render methods by name: each entry has its family, a one-line description, its settings
// (each with a CLI flag, a study-spec key, type, default, range and help) and a factory. The CLI
// (render flags), the study spec and the viewer's menu read this table; adding a method is one
// unit with its entry (render/*_methods.cpp) and one line in render/registry.cpp.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/box.h"
#include "core/result.h"
#include "render/renderer.h"

namespace aquaform {

namespace gpu {
class Context;
}  // namespace gpu

enum class SettingType {
    number,      ///< a float
    integer,     ///< a non-negative integer
    off_switch,  ///< a boolean; the CLI flag (a switch without a value) turns it off
    on_switch,   ///< a boolean; the CLI flag turns it on
    choice,      ///< one of `choices`
};

/// One setting of a method: how users name it and what it accepts. get/set read and write it
/// in a MethodSettings of the entry's family (numbers and integers as double, booleans as 0/1,
/// choices as the index into `choices`).
struct SettingSpec {
    std::string key;       ///< the settings struct's name for it, used in messages
    std::string flag;      ///< the CLI flag ("--step"); empty: none
    std::string spec_key;  ///< the study spec's key; empty: not in the spec
    SettingType type = SettingType::number;
    double min = 0.0, max = 0.0;  ///< closed range (number, integer)
    std::string range;            ///< the range as the messages say it
    std::string help;
    std::vector<std::string> choices;
    std::function<double(const MethodSettings&)> get;
    std::function<void(MethodSettings&, double)> set;

    std::string default_text(const MethodSettings& defaults) const;
};

struct MethodEntry {
    std::string name;         ///< "adaptive", "sbuffer", ...
    std::string family;       ///< "surface", "metaball", "screen_space"
    std::string description;  ///< one line
    bool watchable = true;    ///< quick enough for the viewer's menu
    MethodSettings defaults;  ///< every setting at its default, the method selected
    std::vector<SettingSpec> settings;
    /// Range checks across settings (the family's validate()); the message names the setting.
    std::function<Result<bool>(const MethodSettings&)> validate;
    std::function<std::unique_ptr<Renderer>(gpu::Context&, const ParticleDomain&, uint32_t width, uint32_t height,
                                            uint32_t max_particles, const MethodSettings&)>
        make;

    const SettingSpec* setting_by_flag(const std::string& flag) const;
    const SettingSpec* setting_by_spec_key(const std::string& key) const;
};

class Registry {
public:
    const std::vector<MethodEntry>& entries() const { return entries_; }
    /// The entry of `name`, or nullptr.
    const MethodEntry* find(const std::string& name) const;
    /// The entry of `name`, or an error listing the registered methods.
    Result<const MethodEntry*> lookup(const std::string& name) const;
    /// "adaptive, uniform, ... or narrow_range".
    std::string names() const;

    /// Makes the renderer of settings.method() (a Failure for an unknown method or bad settings).
    std::unique_ptr<Renderer> create(gpu::Context& ctx, const ParticleDomain& domain, uint32_t width, uint32_t height,
                                     uint32_t max_particles, const MethodSettings& settings) const;

    /// Settings of `method` from CLI flags (flag -> value; switches map to ""). Flags that
    /// belong to another family's methods are refused naming the methods they apply to; flags
    /// of no method are ignored (the command's own). Numbers and ranges are checked.
    Result<MethodSettings> from_flags(const std::string& method, const std::map<std::string, std::string>& flags) const;
    /// Settings of `method` from a JSON object of spec keys (other keys are the caller's); `path`
    /// prefixes the messages ("cases[0].methods[1]").
    Result<MethodSettings> from_json(const std::string& method, const nlohmann::json& object,
                                     const std::string& path) const;
    /// Every CLI flag of every method: with a value, and switches.
    std::vector<std::string> value_flags() const;
    std::vector<std::string> switch_flags() const;
    /// The help text: every method with its description, then each family's flags.
    std::string usage() const;

    void add(MethodEntry entry) { entries_.push_back(std::move(entry)); }

private:
    std::vector<MethodEntry> entries_;
};

/// Every registered method.
const Registry& render_registry();

// The families' registrations (their own units).
void register_surface_methods(Registry& registry);       // render/surface_methods.cpp
void register_metaball_methods(Registry& registry);      // render/metaball_methods.cpp
void register_screen_space_methods(Registry& registry);  // render/screen_space_methods.cpp

/// Descriptor helpers for the families' units: a setting bound to a field of `Settings`.
template <typename Settings, typename Field>
SettingSpec setting(std::string key, std::string flag, std::string spec_key, SettingType type, Field Settings::*field,
                    double min, double max, std::string range, std::string help) {
    SettingSpec s;
    s.key = std::move(key);
    s.flag = std::move(flag);
    s.spec_key = std::move(spec_key);
    s.type = type;
    s.min = min;
    s.max = max;
    s.range = std::move(range);
    s.help = std::move(help);
    s.get = [field](const MethodSettings& m) { return double(m.as<Settings>().*field); };
    s.set = [field](MethodSettings& m, double v) {
        if constexpr (std::is_same_v<Field, bool>)
            m.get<Settings>()->*field = v != 0.0;
        else
            m.get<Settings>()->*field = Field(v);
    };
    return s;
}

/// A choice bound to an enum field whose values are the indices of `choices`.
template <typename Settings, typename Enum>
SettingSpec choice(std::string key, std::string flag, std::string spec_key, Enum Settings::*field,
                   std::vector<std::string> choices, std::string help) {
    SettingSpec s;
    s.key = std::move(key);
    s.flag = std::move(flag);
    s.spec_key = std::move(spec_key);
    s.type = SettingType::choice;
    s.choices = std::move(choices);
    s.min = 0;
    s.max = double(s.choices.size() - 1);
    s.help = std::move(help);
    s.get = [field](const MethodSettings& m) { return double(int(m.as<Settings>().*field)); };
    s.set = [field](MethodSettings& m, double v) { m.get<Settings>()->*field = Enum(int(v)); };
    return s;
}

/// The entry of a method drawn by `Adapter` (a FamilyRenderer whose constructor takes the
/// concrete renderer's arguments after the settings) with `defaults` of type `Settings`.
template <typename Adapter, typename Settings>
MethodEntry family_entry(std::string name, std::string family, std::string description, bool watchable,
                         Settings defaults, std::vector<SettingSpec> settings) {
    MethodEntry e;
    e.name = std::move(name);
    e.family = std::move(family);
    e.description = std::move(description);
    e.watchable = watchable;
    e.defaults = MethodSettings(e.name, std::move(defaults));
    e.settings = std::move(settings);
    e.validate = [](const MethodSettings& m) { return validate(m.as<Settings>()); };
    e.make = [](gpu::Context& ctx, const ParticleDomain& domain, uint32_t w, uint32_t h, uint32_t n,
                const MethodSettings& m) {
        return std::unique_ptr<Renderer>(std::make_unique<Adapter>(m, ctx, domain, w, h, n));
    };
    return e;
}

/// A picture size written "640x360", each side within render/picture_size.h's limits.
bool parse_resolution(const std::string& text, uint32_t* width, uint32_t* height);

}  // namespace aquaform
