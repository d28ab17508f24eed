#include "bench/bench_control.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "control/placement.h"
#include "control/raster_placement.h"
#include "control/section_builder.h"
#include "core/error.h"
#include "core/format_text.h"
#include "geometry/primitives.h"
#include "gpu/context.h"
#include "gpu/timer.h"
#include "session/simulation_session.h"
#include "sim/blowup.h"
#include "sim/pbf_params.h"
#include "sim/pbf_solver.h"

namespace aquaform::study {

namespace {

using Clock = std::chrono::steady_clock;
using nlohmann::json;

constexpr double kInsideBudgetS = 60.0;         // longest CPU inside placement we wait for
constexpr float kSphereRadiusPlacement = 0.5f;  // the placement sphere (point counts do not depend on it)
constexpr uint32_t kPlacementSubdivisions = 4;  // 5120 triangles
constexpr int kRepeats = kBenchRepeats;

double ms_since(Clock::time_point start) {
    return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

}  // namespace

// ---- (1) placement ---------------------------------------------------------------------------

/// Lattice points in the bounding box of the triangles: what place_inside() tests.
double lattice_points_in_bounds(const Box& b, float spacing) {
    const glm::dvec3 n = glm::floor(glm::dvec3(b.max - b.min) / double(spacing)) + 1.0;
    return n.x * n.y * n.z;
}

json to_json(const PlacementRow& r) {
    json j = {{"kind", "placement"},
              {"method", r.method},
              {"target_points", r.target},
              {"spacing", r.spacing},
              {"triangles", r.triangles},
              {"points", r.points ? json(*r.points) : json(nullptr)},
              {"ms", r.ms ? json(*r.ms) : json(nullptr)}};
    if (r.gpu_ms) j["gpu_ms"] = *r.gpu_ms;
    if (!r.note.empty()) j["note"] = r.note;
    for (const auto& [k, v] : r.extra.items()) j[k] = v;
    return j;
}

/// The three methods on a sphere whose interior lattice holds about `target` points.
/// `inside_ms_per_test` (ms per lattice point per triangle) comes from the previous size and
/// decides whether the CPU inside placement fits the time budget.
std::vector<PlacementRow> measure_placement(gpu::Context& ctx, uint32_t target, double* inside_ms_per_test,
                                            const BenchProgress& say) {
    const float r = kSphereRadiusPlacement;
    const float spacing = float(std::cbrt(4.0 / 3.0 * M_PI * r * r * r / double(target)));
    const geometry::Mesh mesh = geometry::make_sphere(r, kPlacementSubdivisions);
    const std::vector<glm::vec3> tris = mesh.triangle_soup();
    const Box bounds = control::bounds_of(tris);
    const glm::vec3 origin = control::centred_lattice_origin(bounds, spacing);
    std::vector<PlacementRow> rows;

    {
        PlacementRow row{"vertices", target, spacing, tris.size() / 3};
        say(format_text("placing on the vertices of a %zu-triangle sphere at spacing %.4g (target %u points)",
                        row.triangles, spacing, target));
        for (int i = 0; i < kRepeats; ++i) {
            const control::ControlPoints p = control::place_on_vertices(mesh, spacing);
            row.points = uint32_t(p.points.size());
            if (!row.ms || p.ms < *row.ms) row.ms = p.ms;
        }
        row.note = "surface only: the mesh's vertices plus edge points, thinned";
        rows.push_back(row);
    }

    {
        // O(lattice points * triangles): estimate from the previous size before committing.
        uint32_t subdivisions = kPlacementSubdivisions;
        geometry::Mesh inside_mesh = mesh;
        std::string note;
        bool skip = false;
        if (*inside_ms_per_test > 0.0) {
            const double tests = lattice_points_in_bounds(bounds, spacing) * double(tris.size() / 3);
            const double estimate_s = *inside_ms_per_test * tests / 1000.0;
            if (estimate_s > kInsideBudgetS) {
                subdivisions = kPlacementSubdivisions - 1;
                inside_mesh = geometry::make_sphere(r, subdivisions);
                const double coarse_s = estimate_s * double(inside_mesh.faces.size()) / double(mesh.faces.size());
                note = format_text(
                    "on the %zu-triangle mesh it would take about %.0f s (> %.0f s budget): measured on a coarser "
                    "icosphere (subdivision %u, %zu triangles) instead",
                    mesh.faces.size(), estimate_s, kInsideBudgetS, subdivisions, inside_mesh.faces.size());
                if (coarse_s > kInsideBudgetS) {
                    skip = true;
                    note = format_text("skipped: about %.0f s even on the %zu-triangle icosphere (> %.0f s budget)",
                                       coarse_s, inside_mesh.faces.size(), kInsideBudgetS);
                }
            }
        }
        const std::vector<glm::vec3> inside_tris = inside_mesh.triangle_soup();
        PlacementRow row{"inside", target, spacing, inside_tris.size() / 3};
        row.note = note;
        row.extra["subdivisions"] = subdivisions;
        if (!skip) {
            say(format_text("placing inside the %zu-triangle sphere on the CPU (ray crossings on a triangle grid)",
                            row.triangles));
            // One run: the table says so (it was the slow method once, by winding number).
            const control::ControlPoints p = control::place_inside(inside_tris, spacing, false, 1, origin);
            row.points = uint32_t(p.points.size());
            row.ms = p.ms;
            const double tests =
                lattice_points_in_bounds(control::bounds_of(inside_tris), spacing) * double(row.triangles);
            *inside_ms_per_test = p.ms / tests;
            row.extra["lattice_points_tested"] = lattice_points_in_bounds(control::bounds_of(inside_tris), spacing);
        }
        rows.push_back(row);
    }

    {
        PlacementRow row{"raster", target, spacing, tris.size() / 3};
        say(format_text("placing by GPU rasterisation of the %zu-triangle sphere (warm-up, then best of %d)",
                        row.triangles, kRepeats));
        const glm::dvec3 cells = glm::dvec3(bounds.max - bounds.min) / double(spacing) + 1.0;
        const uint32_t capacity = uint32_t(lattice_points_in_bounds(bounds, spacing));
        const uint32_t pixels = uint32_t((cells.x + 3.0) * (cells.y + 3.0));
        control::RasterPlacer placer(ctx, uint32_t(row.triangles), capacity, pixels);
        control::RasterStats stats = placer.place_on_gpu(tris, spacing, origin);  // warm-up: pipelines, first upload
        if (stats.dropped_points > 0) {
            placer.set_point_capacity(stats.points + stats.dropped_points);
            stats = placer.place_on_gpu(tris, spacing, origin);
        }
        for (int i = 0; i < kRepeats; ++i) {
            stats = placer.place_on_gpu(tris, spacing, origin);
            if (!row.ms || stats.ms < *row.ms) row.ms = stats.ms;
            if (!row.gpu_ms || stats.gpu_ms < *row.gpu_ms) row.gpu_ms = stats.gpu_ms;
        }
        row.points = stats.points;
        row.extra = {{"dropped_points", stats.dropped_points},
                     {"overflowed_pixels", stats.overflowed_pixels},
                     {"open_pixels", stats.open_pixels},
                     {"pixels", stats.pixels}};
        row.note =
            "ms: host wall time of place_on_gpu (upload, both passes, wait, counter read-back); points stay on the GPU";
        rows.push_back(row);
    }
    const PlacementRow& inside = rows[1];
    PlacementRow& raster = rows[2];
    if (inside.points && inside.triangles == raster.triangles && *inside.points > 0)
        raster.extra["points_vs_inside"] = double(*raster.points) / double(*inside.points);
    return rows;
}

// ---- shapes for the solver -------------------------------------------------------------------

constexpr float kSphereRadius = 0.12f;
const glm::vec3 kCentre{0.3f, 0.32f, 0.3f};

float shape_spacing_for(uint32_t particles) {
    return kShapeSpacing * float(std::cbrt(double(kShapeParticles) / double(std::max(particles, 1u))));
}

ShapeScene make_shape_scene(const std::string& name, geometry::Mesh mesh, float shape_height, std::vector<Box> blocks,
                            const std::string& layout, double shape_volume, float spacing) {
    ShapeScene s;
    s.name = name;
    s.layout = layout;
    s.scene.name = "bench control " + name;
    s.scene.domain = {glm::vec3(0.0f), glm::vec3(0.6f)};
    s.scene.particle_spacing = spacing;
    s.scene.fluid_blocks = std::move(blocks);
    for (auto& v : mesh.vertices) v += kCentre;
    s.mesh = mesh;
    s.lattice = {s.scene.domain.min, spacing};
    const auto placed =
        control::place_inside(mesh.triangle_soup(), spacing, false, 1, s.lattice.centre(glm::ivec3(0))).points;
    for (const auto& p : placed) s.points.emplace_back(p, 0.0f);
    s.shape = control::voxel_keys(s.lattice, placed);
    s.strength = control::automatic_strength({&s.scene, spacing, shape_height});
    s.scene.solver.substeps = s.strength.substeps;  // before any solver is built
    s.shape_volume = shape_volume;
    s.fluid_volume = double(s.scene.particle_count()) * spacing * spacing * spacing;
    return s;
}

ShapeScene sphere_scene(float spacing) {
    // 0.0072 m^3 (10 x 9 x 10 particles at 0.02 m), the sphere's 0.00724 m^3 to within 1 %
    const glm::vec3 half(0.1f, 0.09f, 0.1f);
    const double volume = 4.0 / 3.0 * M_PI * std::pow(kSphereRadius, 3.0);
    return make_shape_scene("sphere", geometry::make_sphere(kSphereRadius, 3), 2.0f * kSphereRadius,
                            {{kCentre - half, kCentre + half}}, "box 0.2 x 0.18 x 0.2 m around the centre", volume,
                            spacing);
}

/// A torus of the sphere's volume (R = 3 r), lying flat: its ring in the xz plane. The fluid starts
/// as a square frame of four boxes (0.08 m thick) over the ring, so that none starts over the
/// hole, where no control point pulls it.
ShapeScene torus_scene(float spacing) {
    const double volume = 4.0 / 3.0 * M_PI * std::pow(kSphereRadius, 3.0);
    const float minor = 0.05f;
    const float major = float(volume / (2.0 * M_PI * M_PI * minor * minor));  // 0.1467 m
    geometry::Mesh mesh = geometry::make_torus(major, minor);
    for (auto& v : mesh.vertices) v = glm::vec3(v.x, v.z, -v.y);  // axis z -> y: a proper rotation
    // Frame: outer half-side 0.18, inner 0.10 (the ring spans 0.097 .. 0.197), 0.08 thick:
    // 0.00717 m^3 (at 0.02 m: 224 particles per layer x 4 = 896), the torus's 905 to within 1 %.
    const float a = 0.18f, b = 0.10f, t = 0.04f;
    const glm::vec3 c = kCentre;
    std::vector<Box> frame = {
        {{c.x - a, c.y - t, c.z - a}, {c.x + a, c.y + t, c.z - b}},  // front
        {{c.x - a, c.y - t, c.z + b}, {c.x + a, c.y + t, c.z + a}},  // back
        {{c.x - a, c.y - t, c.z - b}, {c.x - b, c.y + t, c.z + b}},  // left
        {{c.x + b, c.y - t, c.z - b}, {c.x + a, c.y + t, c.z + b}},  // right
    };
    return make_shape_scene(
        "torus", std::move(mesh), 2.0f * minor, std::move(frame),
        format_text("flat torus R = %.4f m, r = %.3f m; fluid: square frame 0.36 m outside, 0.2 m hole, "
                    "0.08 m thick, over the ring",
                    double(major), double(minor)),
        volume, spacing);
}

FillRun::FillRun(gpu::Context& ctx, const ShapeScene& s, float pressure) {
    auto section = control::SectionBuilder(s.scene)
                       .mesh(s.name, s.mesh)
                       .pressure(pressure)
                       .fixed_substeps()
                       .attach(s.name)
                       .build();
    if (!section) throw internal_failure(section.error());  // the bench's own shapes: a bug, not input
    sim = std::make_unique<session::SimulationSession>(ctx, session::plan_session(s.scene, std::move(section.value())),
                                                       session::SessionOptions{false});
}

FillRun::~FillRun() = default;

bool FillRun::advance(double seconds) {
    stats = sim->advance(seconds);
    if (!blowup_verdict(stats, sim->scene()).empty()) return false;  // a sweep row past the stable range
    rms_speed = session::rms_speed(stats, sim->scene());
    return true;
}

control::ShapeMetrics FillRun::metrics(const ShapeScene& s) {
    const ParticleSnapshot snap = sim->solver().snapshot();
    const PbfConstants k = pbf_constants(s.scene);
    return control::shape_metrics({&snap.x, &snap.v, ~0u, k.h, k.mass, s.scene.rest_density}, s.lattice, s.shape);
}

bool FillRun::stable(bool finite) const {
    return finite && std::isfinite(rms_speed) && rms_speed < 0.1 * cfl_speed() &&
           stats.max_density_error < control::kDensityErrorBound;
}

double FillRun::cfl_speed() const {
    const shader::SimParams& p = sim->solver().params();
    return double(sim->scene().solver.cfl) * p.h / p.dt;
}

// ---- (2) the force's share of a step --------------------------------------------------------

double total_of(const std::map<std::string, double>& passes) {
    double sum = 0.0;
    for (const auto& [name, ms] : passes) sum += ms;
    return sum;
}

double median(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

Overhead measure_overhead(gpu::Context& ctx, const ShapeScene& s, double warm_s, uint32_t steps, int repeats,
                          const BenchProgress& say) {
    FillRun run(ctx, s, s.strength.pressure);
    say(format_text(
        "force overhead: filling the sphere for %.2f s, then %d x %u steps with and without the force "
        "(%u particles, %u control points)",
        warm_s, repeats, steps, run.sim->solver().particle_count(), run.sim->control()->force().point_count()));
    run.advance(warm_s);
    require_physical(run.stats, run.sim->scene());  // the overhead of a fluid that left physics means nothing
    PbfSolver& solver = run.sim->solver();
    const ParticleSnapshot start = solver.snapshot();
    gpu::GpuTimer timer(ctx);
    Overhead o;
    o.particles = solver.particle_count();
    o.control_points = run.sim->control()->force().point_count();
    o.steps = steps;
    o.repeats = uint32_t(repeats);
    std::vector<double> added, share, gpu_ratio, wall_ratio;
    // Every run starts from the same state, so both sides step the same fluid; the sides
    // alternate which goes first, so that load from elsewhere hits neither alone.
    for (int r = 0; r < repeats; ++r) {
        double total[2] = {}, wall[2] = {};
        for (bool with : {r % 2 == 0, r % 2 != 0}) {
            with ? solver.attach(&run.sim->control()->force()) : solver.detach(&run.sim->control()->force());
            solver.set_state(start.x, start.v);
            timer.clear_totals();
            solver.run_steps(steps, &timer);
            std::map<std::string, double> passes;
            for (const auto& [name, ms] : timer.totals_ms()) passes[name] = ms / steps;
            solver.set_state(start.x, start.v);
            const auto t0 = Clock::now();
            solver.run_steps(steps, nullptr);  // wall time without the timestamps
            wall[with] = ms_since(t0) / steps;
            total[with] = total_of(passes);
            double& best = with ? o.step_ms_with : o.step_ms_without;
            double& best_wall = with ? o.wall_ms_with : o.wall_ms_without;
            if (r == 0 || total[with] < best) best = total[with], (with ? o.passes_with : o.passes_without) = passes;
            if (r == 0 || wall[with] < best_wall) best_wall = wall[with];
            if (with) {
                const double force = passes.count("control_force") ? passes.at("control_force") : 0.0;
                added.push_back(force / (total[1] - force));
                share.push_back(force / total[1]);
            }
        }
        gpu_ratio.push_back(total[1] / total[0]);
        wall_ratio.push_back(wall[1] / wall[0]);
    }
    o.force_ms = o.passes_with.count("control_force") ? o.passes_with.at("control_force") : 0.0;
    o.added = median(added);
    o.share = median(share);
    o.gpu_with_vs_without = median(gpu_ratio);
    o.wall_with_vs_without = median(wall_ratio);
    return o;
}

// ---- (3) IoU against pressure -----------------------------------------------------------------

json to_json(const SweepRow& r, const ShapeScene& s) {
    json j = {{"kind", "sweep"},
              {"shape", r.shape},
              {"scale", r.scale},
              {"pressure", r.pressure},
              {"automatic_pressure", s.strength.pressure},
              {"seconds", r.seconds},
              {"substeps", s.strength.substeps},
              {"particles", s.scene.particle_count()},
              {"control_points", s.points.size()},
              {"iou", r.finite ? json(r.m.iou) : json(nullptr)},
              {"fill_fraction", r.finite ? json(r.m.fill_fraction) : json(nullptr)},
              {"outside_fraction", r.finite ? json(r.m.outside_fraction) : json(nullptr)},
              {"finite", r.finite},
              {"stable", r.stable},
              {"rms_speed", std::isfinite(r.rms_speed) ? json(r.rms_speed) : json(nullptr)},
              {"cfl_speed", r.cfl_speed},
              {"max_density_error", std::isfinite(r.max_density_error) ? json(r.max_density_error) : json(nullptr)},
              {"wall_s", r.wall_s}};
    if (r.iou_later) j["iou_after_" + format_text("%.2g", r.later_seconds) + "_s"] = *r.iou_later;
    return j;
}

SweepRow sweep_one(gpu::Context& ctx, const ShapeScene& s, double scale, double seconds, double later_seconds) {
    SweepRow row;
    row.shape = s.name;
    row.scale = scale;
    row.pressure = float(s.strength.pressure * scale);
    row.seconds = seconds;
    const auto t0 = Clock::now();
    FillRun run(ctx, s, row.pressure);
    row.finite = run.advance(seconds);
    row.cfl_speed = run.cfl_speed();
    row.rms_speed = run.rms_speed;
    row.max_density_error = run.stats.max_density_error;
    row.stable = run.stable(row.finite);
    if (row.finite) row.m = run.metrics(s);
    if (row.finite && later_seconds > seconds && run.advance(later_seconds - seconds)) {
        row.iou_later = run.metrics(s).iou;
        row.later_seconds = later_seconds;
    }
    row.wall_s = ms_since(t0) / 1000.0;
    return row;
}

}  // namespace aquaform::study
