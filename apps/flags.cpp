#include "apps/flags.h"

#include <algorithm>

#include "core/number_text.h"
#include "render/registry.h"
#include "sim/scene.h"

namespace aquaform::cli {

std::string Args::value(const std::string& flag, const std::string& fallback) const {
    auto it = values.find(flag);
    return it == values.end() ? fallback : it->second;
}

std::optional<Args> parse_args(const std::vector<std::string>& argv, const FlagSpec& spec, const std::string& command,
                               std::string* error) {
    Args args;
    auto contains = [](const std::vector<std::string>& v, const std::string& s) {
        return std::find(v.begin(), v.end(), s) != v.end();
    };
    for (size_t i = 0; i < argv.size(); ++i) {
        const std::string& a = argv[i];
        if (a.rfind("--", 0) != 0) {
            args.positional.push_back(a);
            continue;
        }
        if (contains(spec.switches, a)) {
            args.switches[a] = true;
        } else if (contains(spec.with_value, a)) {
            if (i + 1 >= argv.size()) {
                *error = "aquaform " + command + ": " + a + " needs a value";
                return std::nullopt;
            }
            args.values[a] = argv[++i];
        } else {
            std::string known;
            for (const auto& f : spec.with_value) known += " " + f;
            for (const auto& f : spec.switches) known += " " + f;
            *error = "aquaform " + command + ": unknown flag " + a +
                     "; known flags:" + (known.empty() ? " (none)" : known) + " (see aquaform " + command + " --help)";
            return std::nullopt;
        }
    }
    return args;
}

std::optional<long> parse_positive(const std::string& flag, const std::string& text, std::string* error, long max) {
    const std::optional<uint64_t> v = number_text::whole_number(text);
    if (!v || *v < 1 || *v > uint64_t(max)) {
        *error = flag + " must be a whole number from 1 to " + std::to_string(max) + ", got \"" + text + "\"";
        return std::nullopt;
    }
    return long(*v);
}

std::optional<uint32_t> parse_frame_index(const std::string& flag, const std::string& text, std::string* error) {
    const std::optional<uint64_t> v = number_text::whole_number(text);
    if (!v || *v >= uint64_t(kMaxFrames)) {
        *error =
            flag + " must be a frame number from 0 to " + std::to_string(kMaxFrames - 1) + ", got \"" + text + "\"";
        return std::nullopt;
    }
    return uint32_t(*v);
}

std::optional<std::vector<std::string>> parse_list(const std::string& flag, const std::string& text,
                                                   const std::string& example, std::string* error) {
    auto items = number_text::split_list(text);
    if (!items)
        *error = flag + (text.empty() ? " is empty" : " has an empty item in \"" + text + "\"") +
                 "; give its values separated by single commas, e.g. " + flag + " " + example;
    return items;
}

std::optional<std::vector<double>> parse_positive_numbers(const std::string& flag, const std::string& text,
                                                          const std::string& example, std::string* error) {
    const auto items = parse_list(flag, text, example, error);
    if (!items) return std::nullopt;
    std::vector<double> numbers;
    for (const std::string& item : *items) {
        const std::optional<double> v = number_text::finite_number(item);
        if (!v || *v <= 0.0) {
            *error = flag + " takes positive numbers, e.g. " + flag + " " + example + "; got \"" + item + "\"";
            return std::nullopt;
        }
        numbers.push_back(*v);
    }
    return numbers;
}

std::vector<uint32_t> parse_sizes(const std::string& text, std::string* error) {
    std::vector<uint32_t> sizes;
    const auto items = parse_list("--sizes", text, "16384,65536", error);
    if (!items) return {};
    for (const std::string& item : *items) {
        auto v = parse_positive("--sizes", item, error, long(kMaxSceneParticles));
        if (!v) return {};
        sizes.push_back(static_cast<uint32_t>(*v));
    }
    return sizes;
}

std::optional<uint64_t> particles_flag(const Args& args, std::string* error) {
    error->clear();
    if (!args.has("--particles")) return std::nullopt;
    const std::string text = args.value("--particles");
    const uint64_t v = number_text::whole_number(text).value_or(0);
    if (v < kMinSceneParticles || v > kMaxSceneParticles) {
        *error = "--particles must be a particle count from " + std::to_string(kMinSceneParticles) + " to " +
                 std::to_string(kMaxSceneParticles) + ", got \"" + text + "\"";
        return std::nullopt;
    }
    return v;
}

bool scale_to_particles_flag(const Args& args, Scene& scene, std::string* error) {
    const std::optional<uint64_t> n = particles_flag(args, error);
    if (!n) return error->empty();
    auto scaled = with_particle_count(scene, *n);
    if (!scaled) return *error = scaled.error(), false;
    scene = std::move(scaled.value());
    return true;
}

bool apply_whitewater_flag(const Args& args, Scene& scene, std::string* error) {
    if (!args.has("--whitewater")) return true;
    const std::string& value = args.value("--whitewater");
    if (value != "on" && value != "off") return *error = "--whitewater takes on or off, got \"" + value + "\"", false;
    if (value == "on" || scene.whitewater) {
        scene.whitewater = scene.whitewater.value_or(WhitewaterSettings{});
        scene.whitewater->enabled = value == "on";
    }
    return true;
}

std::optional<PictureSize> resolution_flag(const Args& args, PictureSize fallback, std::string* error,
                                           const std::string& flag) {
    if (!args.has(flag)) return fallback;
    PictureSize size;
    if (parse_resolution(args.value(flag), &size.width, &size.height)) return size;
    *error = flag + " must look like " + fallback.text() + " (WIDTHxHEIGHT, each side " + picture_side_range() +
             "), got \"" + args.value(flag) + "\"";
    return std::nullopt;
}

}  // namespace aquaform::cli
