// The metaball methods in the registry (Karpati et al.): brute force, A-buffer and S-buffer.
#include "render/metaball_renderer.h"
#include "render/registry.h"

namespace aquaform {

namespace {

class MetaballMethodRenderer final : public FamilyRenderer<MetaballRenderer, MetaballSettings> {
public:
    using FamilyRenderer::FamilyRenderer;
    RenderStats stats() override {
        const MetaballStats m = impl_.stats();
        RenderStats s;
        s.rays = uint64_t(impl_.width()) * impl_.height();
        s.evaluations = m.field_evaluations;
        s.list_entries = m.list_entries;
        s.particle_visits = m.kernel_evaluations;
        s.cut = m.cut_pixels;
        s.cut_unit = "pixels";
        s.list_overflow = m.overflow;
        s.list_bytes_needed = m.list_bytes_needed;
        s.dropped_particles = m.near_kept ? 0 : m.dropped_particles;
        s.family_line = m.describe();
        return s;
    }
};

using S = MetaballSettings;
constexpr SettingType kNumber = SettingType::number, kInteger = SettingType::integer;

std::vector<SettingSpec> metaball_settings() {
    return {
        choice<S>("visual", "--visual", "visual", &S::visual, {"gradient", "real"},
                  "gradient: normal colours; real: reflection and refraction"),
        setting<S>("size", "--metaball-size", "size", kNumber, &S::size, 0.5, 8,
                   "a number of particle spacings from 0.5 to 8", "metaball range in particle spacings"),
        setting<S>("iso", "--iso", "iso", kNumber, &S::iso, 0, 1, "0 < iso < 1 (a lone ball's peak is 1)",
                   "iso value of the field"),
        setting<S>("step", "--step", "step", kNumber, &S::step_radii, 0.01, 4, "0.01..4 particle radii",
                   "marching step in particle radii"),
        setting<S>("max_steps", "--max-steps", "max_steps", kInteger, &S::max_steps, 1, 1000000, "1..1000000",
                   "field evaluations per ray segment before it gives up"),
        setting<S>("bisection_steps", "--bisection", "bisection", kInteger, &S::bisection_steps, 0, 32, "0..32",
                   "bisection steps at the hit"),
        setting<S>("recursion_depth", "--recursion", "recursion", kInteger, &S::recursion_depth, 1, 4, "1..4",
                   "surface interactions of the real visual"),
        setting<S>("keep_near", "--keep-near", "keep_near", SettingType::on_switch, &S::keep_near, 0, 1, "",
                   "visit the particles at the eye plane from a near list"),
        setting<S>("list_bytes_per_pixel", "--list-bytes", "list_bytes_per_pixel", kInteger, &S::list_bytes_per_pixel,
                   0, 65536, "0 (256) or 8..65536 bytes per pixel", "list memory per pixel"),
    };
}

void add(Registry& registry, MetaballMethod method, const char* name, const char* description) {
    MetaballSettings defaults;
    defaults.method = method;
    MethodEntry e = family_entry<MetaballMethodRenderer>(
        name, "metaball", description, method != MetaballMethod::brute_force, defaults, metaball_settings());
    // The list memory is the renderer's, fixed when it is made.
    e.make = [](gpu::Context& ctx, const ParticleDomain& domain, uint32_t w, uint32_t h, uint32_t n,
                const MethodSettings& m) {
        const uint64_t list_bytes = uint64_t(m.as<MetaballSettings>().list_bytes_per_pixel) * w * h;
        return std::unique_ptr<Renderer>(std::make_unique<MetaballMethodRenderer>(m, ctx, domain, w, h, n, list_bytes));
    };
    registry.add(std::move(e));
}

}  // namespace

void register_metaball_methods(Registry& registry) {
    add(registry, MetaballMethod::brute_force, "brute", "metaballs, brute force: every particle at every step (slow)");
    add(registry, MetaballMethod::a_buffer, "abuffer", "metaballs from per-pixel linked lists (A-buffer)");
    add(registry, MetaballMethod::s_buffer, "sbuffer", "metaballs from contiguous per-pixel lists (S-buffer)");
}

}  // namespace aquaform
