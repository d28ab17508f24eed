// `aquaform view SCENE`: the interactive viewer. A GLFW window presents the renderer's image
// straight from its GPU buffer (apps/view_window.h); Dear ImGui panels play, pause, step and
// reset the simulation, switch the surface method and change solver settings, and chart the
// GPU time per pass; an OBJ dropped on the window becomes the shape the fluid fills (Release lets
// it go). Dragging with the left button pushes the fluid; the right button orbits, the middle
// pans and the wheel zooms the camera; F switches to a fly camera (right button looks around,
// W/A/S/D/Q/E move).
// Keys: space play/pause, N one step, R reset, P screenshot, Esc quit. --script plays UI actions
// at given frames (apps/view_script.h); --record DIR writes every frame drawn. Shaders edited
// while it runs are recompiled and reloaded (gpu/shader_compiler.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <utility>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "apps/cli.h"
#include "apps/render_options.h"
#include "apps/view_script.h"
#include "apps/view_shapes.h"
#include "apps/view_window.h"
#include "control/control_driver.h"
#include "control/push_force.h"
#include "gpu/context.h"
#include "gpu/shader_compiler.h"
#include "gpu/shader_registry.h"
#include "gpu/timer.h"
#include "gpu/vk_check.h"
#include "render/surface_settings.h"
#include "render/image_io.h"
#include "render/image_metrics.h"
#include "render/surface_views.h"
#include "render/metaball_renderer.h"
#include "render/screen_space.h"
#include "render/surface_renderer.h"
#include "sim/pbf_solver.h"

namespace aquaform::cli {

namespace {

namespace fs = std::filesystem;

/// The method menu: every renderer that is quick enough to watch.
constexpr const char* kMethods[] = {"adaptive", "uniform", "sbuffer", "abuffer", "narrow_range", "bilateral", "curvature_flow"};
constexpr size_t kHistory = 120;  // frames in the timing chart
/// Debug views of the SPH renderer (Wu et al. Figs. 5-7 and the depth maps).
constexpr const char* kViews[] = {"image", "steps per ray", "classification", "tile resolution", "D_all", "D_agg"};
constexpr const char* kViewNames[] = {"image", "steps", "classification", "tiles", "depth_all", "depth_agg"};  // in scripts

/// Files dropped onto the window since the last frame (GLFW calls back with no user data to
/// spare: the ImGui backend owns the window's callbacks, and there is one viewer per process).
std::vector<std::string> g_dropped;
void on_drop(GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i) g_dropped.emplace_back(paths[i]);
}

class Viewer {
public:
    Viewer(gpu::Context& ctx, ViewWindow& window, Scene scene, std::optional<control::PreparedControl> control,
           SurfaceSettings surface_settings)
        : ctx_(ctx), window_(window), scene_(std::move(scene)), control_(std::move(control)),
          surface_settings_(surface_settings), render_timer_(ctx), sim_timer_(ctx), push_(ctx) {
        rebuild_solver(false);
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_.handle(), &w, &h);
        orbit_ = OrbitCamera::around(camera_for_domain(scene_.domain, float(std::max(w, 1)) / float(std::max(h, 1))));
        init_ui();
        glfwSetDropCallback(window_.handle(), on_drop);
    }
    ~Viewer() {
        vkDeviceWaitIdle(ctx_.device());
        ImGui_ImplVulkan_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        if (ui_pool_) vkDestroyDescriptorPool(ctx_.device(), ui_pool_, nullptr);
    }

    int run(const std::vector<ViewAction>& script, const fs::path& record_dir, uint32_t max_frames) {
        size_t next_action = 0;
        const auto start = std::chrono::steady_clock::now();
        uint32_t frame = 0;
        for (; !window_.should_close() && !quit_ && (max_frames == 0 || frame < max_frames); ++frame) {
            glfwPollEvents();
            while (next_action < script.size() && script[next_action].frame <= frame) apply(script[next_action++]);
            for (const std::string& file : std::exchange(g_dropped, {})) attach_mesh(file);
            if (watcher_ && frame % 15 == 0) reload_shaders();
            if (quit_) break;
            if (playing_ || step_once_) advance();
            step_once_ = false;
            if (!draw(frame)) continue;
            if (!record_dir.empty()) {
                char name[32];
                std::snprintf(name, sizeof name, "frame_%04u.png", frame);
                screenshot(record_dir / name);
            }
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::printf("aquaform view: %u frames in %.1f s (%.2f frames/s, %u particles, %ux%u, %s)\n", frame, seconds,
                    seconds > 0 ? frame / seconds : 0.0, solver_->particle_count(), render_w_, render_h_, method_.c_str());
        return failed_ ? kExitFailure : kExitOk;
    }

    void set_screenshot_dir(const fs::path& dir) { screenshot_dir_ = dir; }
    /// Watch `dir` (a shader tree like shaders/) and reload shaders edited while the viewer runs.
    void watch_shaders(const fs::path& dir) { watcher_ = std::make_unique<gpu::ShaderWatcher>(dir); }
    void set_method(const std::string& method) { method_ = method; }

private:
    // ---- simulation -------------------------------------------------------------------------

    /// A fresh solver from the scene, or (keep_state) one with the new settings continuing from
    /// the current particles: the solver's settings are fixed at construction.
    void rebuild_solver(bool keep_state) {
        std::optional<ParticleSnapshot> state;
        if (keep_state && solver_) state = solver_->snapshot();
        driver_.reset();
        solver_ = std::make_unique<PbfSolver>(ctx_, scene_);
        if (state) solver_->set_state(state->x, state->v);
        if (control_) driver_ = std::make_unique<control::ControlDriver>(ctx_, scene_, control_->section, control_->strength);
        forces_.forces = {driver_ ? &driver_->force() : nullptr, &push_};
        solver_->set_step_force(&forces_);
    }

    void advance() {
        if (driver_) driver_->update(solver_->time());
        const FrameStats stats = solver_->run_frame(&sim_timer_);
        sim_passes_ = sim_timer_.totals_ms();
        if (stats.non_finite > 0 && playing_) {
            playing_ = false;
            status_ = "the simulation blew up (" + std::to_string(stats.non_finite) +
                      " particles not finite): raise substeps or reset";
        }
    }

    /// Recompiles edited shaders; passes are made again (renderers and solver), so they pick
    /// the new code up. A shader that does not compile keeps its old code and shows the error.
    void reload_shaders() {
        const gpu::ShaderWatcher::Reload r = watcher_->poll();
        for (const std::string& e : r.errors) std::fprintf(stderr, "aquaform view: %s\n", e.c_str());
        if (!r.errors.empty()) status_ = r.errors.front();
        if (r.reloaded.empty()) return;
        vkDeviceWaitIdle(ctx_.device());
        render_w_ = render_h_ = 0;  // renderers are rebuilt at the next frame
        rebuild_solver(true);
        if (r.errors.empty()) status_ = "reloaded " + std::to_string(r.reloaded.size()) + " shaders (" + r.reloaded.front() + (r.reloaded.size() > 1 ? ", ..." : "") + ")";
        std::printf("aquaform view: %s\n", status_.c_str());
    }

    // ---- rendering --------------------------------------------------------------------------

    /// Renderers match the window's framebuffer; they are made again when it changes size.
    void ensure_renderers(uint32_t w, uint32_t h) {
        if (w == render_w_ && h == render_h_) return;
        vkDeviceWaitIdle(ctx_.device());
        surface_.reset();
        metaball_.reset();
        screen_space_.reset();
        render_w_ = w;
        render_h_ = h;
    }

    const gpu::Buffer& record_render(VkCommandBuffer cmd) {
        const ViewCamera camera = orbit_.camera();
        const uint32_t n = solver_->particle_count();
        if (method_ == "adaptive" || method_ == "uniform") {
            if (!surface_) surface_ = std::make_unique<SurfaceRenderer>(ctx_, scene_, render_w_, render_h_, n);
            SurfaceSettings s = surface_settings_;
            s.method = method_ == "adaptive" ? SurfaceMethod::adaptive : SurfaceMethod::uniform;
            if (view_ != 0) return debug_view(camera, s);
            surface_->record(cmd, solver_->positions(), n, camera, s, &render_timer_);
            return surface_->color_buffer();
        }
        if (method_ == "sbuffer" || method_ == "abuffer") {
            if (!metaball_) metaball_ = std::make_unique<MetaballRenderer>(ctx_, scene_, render_w_, render_h_, n);
            MetaballSettings s;
            s.method = parse_metaball_method(method_).value();
            metaball_->record(cmd, solver_->positions(), n, camera, s, &render_timer_);
            return metaball_->color_buffer();
        }
        if (!screen_space_) screen_space_ = std::make_unique<ScreenSpaceRenderer>(ctx_, scene_, render_w_, render_h_, n);
        ScreenSpaceSettings s;
        s.filter = parse_filter(method_).value();
        screen_space_->record(cmd, solver_->positions(), n, camera, s, &render_timer_);
        return screen_space_->color_buffer();
    }

    /// A debug view of the SPH renderer: rendered in a submission of its own, read back and drawn
    /// on the host (diagnostics only: the main view never leaves the GPU), then shown like a frame.
    const gpu::Buffer& debug_view(const ViewCamera& camera, const SurfaceSettings& s) {
        surface_->set_diagnostics(view_ == 2);
        const SurfaceFrame frame = surface_->render(solver_->positions(), solver_->particle_count(), camera, s);
        Image image;
        // Depth maps: near bright, far dark, pixels no sprite covers left as the image.
        auto depth_view = [&](std::vector<float> depth) {
            float lo = INFINITY, hi = 0.0f;
            for (float d : depth)
                if (std::isfinite(d)) lo = std::min(lo, d), hi = std::max(hi, d);
            const float range = std::max(hi - lo, 1e-6f);
            for (float& d : depth) d = std::isfinite(d) ? 0.05f + (hi - d) / range : 0.0f;
            return heat_map(depth, render_w_, render_h_, 1.05f, &frame.color);
        };
        switch (view_) {
        case 1: image = evals_view(frame, float(s.max_steps) / 4.0f); break;
        case 2: image = classification_view(frame.color, surface_->front_classes()); break;
        case 3: image = tile_view(frame.color, surface_->tile_levels(), surface_->params().screen.z); break;
        case 4: image = depth_view(surface_->depth_all()); break;
        default: image = depth_view(surface_->depth_agg()); break;
        }
        const uint64_t bytes = image.rgba.size();
        if (!debug_image_ || debug_image_->size < bytes) {
            vkDeviceWaitIdle(ctx_.device());
            debug_image_.reset(new gpu::Buffer(gpu::create_buffer(ctx_, "view.debug_image", bytes, gpu::MemoryUse::host)));
        }
        std::memcpy(debug_image_->mapped, image.rgba.data(), bytes);
        return *debug_image_;
    }

    /// One window frame: render, blit, UI, present. False when nothing was drawn (minimised).
    bool draw(uint32_t frame) {
        VkCommandBuffer cmd = window_.begin_frame();
        if (timer_pending_) {
            timer_pending_ = false;
            render_timer_.collect();
            render_passes_ = render_timer_.totals_ms();
            double total = 0.0;
            for (const auto& [name, ms] : render_passes_) total += ms;
            history_.push_back(float(total));
            if (history_.size() > kHistory) history_.pop_front();
        }
        if (!cmd) return false;
        const VkExtent2D extent = window_.extent();
        ensure_renderers(std::max(extent.width, 16u), std::max(extent.height, 16u));
        render_timer_.reset(cmd);
        const gpu::Buffer& color = record_render(cmd);
        last_color_ = &color;
        window_.blit(cmd, color, render_w_, render_h_);
        ImGui_ImplVulkan_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        handle_input();
        panel(frame);
        ImGui::Render();
        window_.begin_ui(cmd);
        ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
        window_.end_ui(cmd);
        window_.end_frame(cmd);
        timer_pending_ = true;
        return true;
    }

    /// The last rendered frame (without the UI) as PNG.
    void screenshot(const fs::path& path) {
        if (!last_color_) return;
        vkDeviceWaitIdle(ctx_.device());
        Image image;
        image.width = render_w_;
        image.height = render_h_;
        image.rgba.resize(size_t(render_w_) * render_h_ * 4);
        gpu::download(ctx_, *last_color_, image.rgba.data(), image.rgba.size());
        std::error_code ec;
        if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
        auto written = write_png(path, image);
        if (!written) {
            std::fprintf(stderr, "aquaform view: %s\n", written.error().c_str());
            failed_ = true;
        } else {
            status_ = "saved " + path.string();
        }
    }

    // ---- interaction ------------------------------------------------------------------------

    void apply(const ViewAction& a) {
        if (a.what == "play") playing_ = true;
        else if (a.what == "pause") playing_ = false;
        else if (a.what == "step") step_once_ = true;
        else if (a.what == "reset") rebuild_solver(false);
        else if (a.what == "quit") quit_ = true;
        else if (a.what == "screenshot") screenshot(fs::path(a.value).is_absolute() ? fs::path(a.value) : screenshot_dir_ / a.value);
        else if (a.what == "method") set_method_checked(a.value);
        else if (a.what == "attach") shape(ShapeOp::attach, a.value);
        else if (a.what == "union") shape(ShapeOp::union_with, a.value);
        else if (a.what == "morph") shape(ShapeOp::morph, a.value);
        else if (a.what == "view") set_view_checked(a.value);
        else if (a.what == "release") release();
        else if (a.what == "iterations" || a.what == "substeps") {
            (a.what == "iterations" ? scene_.solver.iterations : scene_.solver.substeps) = uint32_t(std::stoul(a.value));
            rebuild_solver(true);
        }
    }

    /// Applies a shape operation with `file` (an OBJ): attach makes it the only shape, union adds
    /// it to the shapes, morph hands the shapes over to it in one second (apps/view_shapes.h says
    /// where it goes), at the automatic strength; the solver continues from the current particles.
    /// A mesh that cannot be used leaves the simulation as it was and says why.
    void shape(ShapeOp op, const fs::path& file) {
        std::vector<fs::path> meshes = op == ShapeOp::attach ? std::vector<fs::path>{} : shape_files_;
        meshes.push_back(fs::absolute(file));
        Scene trial = scene_;
        trial.control_json = shape_section(meshes, op, shape_box(scene_, solver_->snapshot().x));
        auto prepared = control::prepare_control_scene(trial);
        if (!prepared) {
            status_ = "cannot use " + file.string() + ": " + prepared.error();
            std::fprintf(stderr, "aquaform view: %s\n", status_.c_str());
            return;
        }
        scene_ = trial;
        control_ = std::move(prepared.value());
        shape_files_ = op == ShapeOp::morph ? std::vector<fs::path>{meshes.back()} : meshes;
        rebuild_solver(true);
        const char* verb = op == ShapeOp::attach ? "attached" : op == ShapeOp::union_with ? "added" : "morphing to";
        status_ = std::string(verb) + " " + file.filename().string() + " (" + control_->strength.describe() + ")";
        std::printf("aquaform view: %s\n", status_.c_str());
    }
    void attach_mesh(const fs::path& file) { shape(ShapeOp::attach, file); }

    /// Control off: the fluid returns to plain physics from the current particles.
    void release() {
        if (!control_) return;
        control_.reset();
        shape_files_.clear();
        scene_.control_json.reset();
        rebuild_solver(true);
        status_ = "released the control shape";
        std::printf("aquaform view: %s\n", status_.c_str());
    }

    void set_view_checked(const std::string& name) {
        const auto it = std::find(std::begin(kViewNames), std::end(kViewNames), name);
        if (it == std::end(kViewNames)) {
            std::fprintf(stderr, "aquaform view: unknown view \"%s\" in the script; use image, steps, classification, "
                                 "tiles, depth_all or depth_agg\n", name.c_str());
            failed_ = true;
            return;
        }
        view_ = int(it - std::begin(kViewNames));
    }

    void set_method_checked(const std::string& method) {
        if (std::find(std::begin(kMethods), std::end(kMethods), method) == std::end(kMethods)) {
            std::fprintf(stderr, "aquaform view: unknown method \"%s\" in the script; use one of the method menu's\n",
                         method.c_str());
            failed_ = true;
            return;
        }
        method_ = method;
    }

    /// Left drag pushes the fluid near the mouse ray along the drag; right drag orbits, middle
    /// drag pans, the wheel zooms.
    void handle_input() {
        ImGuiIO& io = ImGui::GetIO();
        push_.clear();
        if (!io.WantCaptureMouse) {
            const ViewCamera camera = orbit_.camera();
            const glm::mat3 axes = camera_axes(camera);
            // World metres per pixel at the orbit's target.
            const float metres_per_px = 2.0f * orbit_.distance * std::tan(glm::radians(orbit_.fov) * 0.5f) /
                                        std::max(io.DisplaySize.y, 1.0f);
            if (ImGui::IsMouseDragging(ImGuiMouseButton_Left) && solver_) {
                const CameraBlock view = camera_block(camera, uint32_t(std::max(io.DisplaySize.x, 1.0f)),
                                                      uint32_t(std::max(io.DisplaySize.y, 1.0f)));
                const float u = 2.0f * io.MousePos.x / std::max(io.DisplaySize.x, 1.0f) - 1.0f;
                const float v = 2.0f * io.MousePos.y / std::max(io.DisplaySize.y, 1.0f) - 1.0f;
                const glm::vec3 dir = glm::normalize(glm::vec3(view.forward) + u * view.forward.w * glm::vec3(view.right) -
                                                     v * view.right.w * glm::vec3(view.up));
                const glm::vec3 drag = (io.MouseDelta.x * axes[0] - io.MouseDelta.y * axes[1]) * metres_per_px;
                // A drag of one centimetre per frame accelerates the fluid at about 1 g.
                const glm::vec3 accel = drag * 1000.0f;
                const float radius = std::max(4.0f * scene_.particle_spacing, 0.05f * orbit_.distance);
                if (glm::length(accel) > 0.0f) push_.set(camera.eye, dir, radius, accel);
            }
            if (ImGui::IsMouseDragging(ImGuiMouseButton_Right))
                orbit_.turn(-io.MouseDelta.x * 0.01f, (fly_ ? -1.0f : 1.0f) * io.MouseDelta.y * 0.01f, fly_);
            if (ImGui::IsMouseDragging(ImGuiMouseButton_Middle))
                orbit_.target += (-io.MouseDelta.x * axes[0] + io.MouseDelta.y * axes[1]) * metres_per_px;
            if (io.MouseWheel != 0.0f) orbit_.distance *= std::pow(0.9f, io.MouseWheel);
        }
        // ImGui 1.86's GLFW backend indexes the key state by GLFW key codes.
        if (!io.WantCaptureKeyboard) {
            if (ImGui::IsKeyPressed(GLFW_KEY_F)) fly_ = !fly_;
            if (fly_) {
                // W/S forward and back, A/D sideways, Q/E down and up, half the domain per second.
                const glm::mat3 axes = camera_axes(orbit_.camera());
                const float speed = 0.5f * glm::length(scene_.domain.max - scene_.domain.min) * io.DeltaTime;
                const std::pair<int, glm::vec3> moves[] = {{GLFW_KEY_W, axes[2]}, {GLFW_KEY_S, -axes[2]}, {GLFW_KEY_D, axes[0]},
                                                           {GLFW_KEY_A, -axes[0]}, {GLFW_KEY_E, axes[1]}, {GLFW_KEY_Q, -axes[1]}};
                for (const auto& [key, axis] : moves)
                    if (ImGui::IsKeyDown(key)) orbit_.target += speed * axis;
            }
            if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) playing_ = !playing_;
            if (ImGui::IsKeyPressed(GLFW_KEY_N)) step_once_ = true;
            if (ImGui::IsKeyPressed(GLFW_KEY_R)) rebuild_solver(false);
            if (ImGui::IsKeyPressed(GLFW_KEY_P)) screenshot(screenshot_dir_ / ("screenshot_" + std::to_string(shots_++) + ".png"));
            if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) quit_ = true;
        }
    }

    void panel(uint32_t frame) {
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(300, 0), ImGuiCond_FirstUseEver);
        ImGui::Begin("aquaform");
        ImGui::Text("%s: %u particles, t = %.3f s", scene_.name.c_str(), solver_->particle_count(), solver_->time());
        ImGui::Text("frame %u, %.1f frames/s", frame, ImGui::GetIO().Framerate);
        if (ImGui::Button(playing_ ? "Pause" : "Play")) playing_ = !playing_;
        ImGui::SameLine();
        if (ImGui::Button("Step")) step_once_ = true;
        ImGui::SameLine();
        if (ImGui::Button("Reset")) rebuild_solver(false);
        if (ImGui::BeginCombo("method", method_.c_str())) {
            for (const char* m : kMethods)
                if (ImGui::Selectable(m, method_ == m)) method_ = m;
            ImGui::EndCombo();
        }
        if (ImGui::CollapsingHeader("Solver", ImGuiTreeNodeFlags_DefaultOpen)) {
            int iterations = int(scene_.solver.iterations), substeps = int(scene_.solver.substeps);
            bool changed = ImGui::SliderInt("iterations", &iterations, 1, 16);
            changed |= ImGui::SliderInt("substeps", &substeps, 1, 16);
            changed |= ImGui::SliderFloat("viscosity", &scene_.solver.viscosity, 0.0f, 0.2f);
            changed |= ImGui::SliderFloat("vorticity", &scene_.solver.vorticity, 0.0f, 0.01f, "%.4f");
            if (changed && ImGui::IsItemDeactivatedAfterEdit()) {
                scene_.solver.iterations = uint32_t(iterations);
                scene_.solver.substeps = uint32_t(substeps);
                rebuild_solver(true);
            } else {
                scene_.solver.iterations = uint32_t(iterations);
                scene_.solver.substeps = uint32_t(substeps);
            }
        }
        if (ImGui::CollapsingHeader("Shape", ImGuiTreeNodeFlags_DefaultOpen)) {
            ImGui::InputText("mesh", mesh_path_, sizeof mesh_path_);
            if (ImGui::Button("Attach")) shape(ShapeOp::attach, mesh_path_);
            ImGui::SameLine();
            if (ImGui::Button("Union") && control_) shape(ShapeOp::union_with, mesh_path_);
            ImGui::SameLine();
            if (ImGui::Button("Morph") && control_) shape(ShapeOp::morph, mesh_path_);
            ImGui::SameLine();
            if (ImGui::Button("Release")) release();
            if (control_)
                for (const fs::path& f : shape_files_) ImGui::BulletText("%s", f.filename().string().c_str());
            else
                ImGui::TextDisabled("no shape: type a mesh path or drop an OBJ on the window");
        }
        if ((method_ == "adaptive" || method_ == "uniform") && ImGui::CollapsingHeader("Renderer")) {
            SurfaceSettings& r = surface_settings_;
            const SurfaceSettings before = r;
            ImGui::Combo("view", &view_, kViews, IM_ARRAYSIZE(kViews));
            ImGui::Checkbox("mask", &r.use_mask);
            ImGui::SameLine();
            ImGui::Checkbox("skip", &r.use_skip);
            ImGui::SameLine();
            ImGui::Checkbox("adaptive res.", &r.adaptive_resolution);
            ImGui::Checkbox("blend normals", &r.blend_normals);
            ImGui::SameLine();
            ImGui::Checkbox("anisotropic", &r.anisotropic);
            ImGui::SliderFloat("iso (lone radius)", &r.lone_radius, 0.2f, 3.0f);
            ImGui::SliderFloat("step [radii]", &r.step_radii, 0.1f, 4.0f);
            ImGui::SliderFloat("mask a", &r.mask_a, 0.05f, 1.0f);
            ImGui::SliderFloat("mask b", &r.mask_b, 0.05f, 1.0f);
            ImGui::SliderFloat("eps1 [radii^2]", &r.tile_eps1, 0.0f, 16.0f);
            ImGui::SliderFloat("eps2 [radii^2]", &r.tile_eps2, 0.1f, 64.0f);
            ImGui::SliderFloat("blend A", &r.blend_a, 0.0f, 1.0f);
            ImGui::SliderFloat("blend B", &r.blend_b, -0.5f, 0.5f);
            int skip = int(r.max_skip_evals);
            if (ImGui::SliderInt("maxSkipCounts", &skip, 1, 64)) r.max_skip_evals = uint32_t(skip);
            if (auto valid = validate(r); !valid) {
                status_ = valid.error();
                r = before;  // keep the last settings the renderer accepts
            }
        }
        if (ImGui::CollapsingHeader("GPU time", ImGuiTreeNodeFlags_DefaultOpen)) {
            std::vector<float> history(history_.begin(), history_.end());
            if (!history.empty())
                ImGui::PlotLines("render ms", history.data(), int(history.size()), 0, nullptr, 0.0f, FLT_MAX, ImVec2(0, 60));
            for (const auto& [name, ms] : render_passes_) ImGui::Text("%-22s %8.2f ms", name.c_str(), ms);
            double sim = 0.0;
            for (const auto& [name, ms] : sim_passes_) sim += ms;
            ImGui::Text("%-22s %8.2f ms", "simulation (frame)", sim);
        }
        ImGui::Checkbox("fly camera (F; WASD, Q/E)", &fly_);
        if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
        ImGui::End();
    }

    void init_ui() {
        IMGUI_CHECKVERSION();
        ImGui::CreateContext();
        ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the user's files
        ImGui::StyleColorsDark();
        VkDescriptorPoolSize sizes[] = {{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16}};
        VkDescriptorPoolCreateInfo pool{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        pool.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
        pool.maxSets = 16;
        pool.poolSizeCount = 1;
        pool.pPoolSizes = sizes;
        VK_CHECK(vkCreateDescriptorPool(ctx_.device(), &pool, nullptr, &ui_pool_));
        ImGui_ImplGlfw_InitForVulkan(window_.handle(), true);
        ImGui_ImplVulkan_InitInfo info{};
        info.Instance = ctx_.instance();
        info.PhysicalDevice = ctx_.physical_device();
        info.Device = ctx_.device();
        info.QueueFamily = ctx_.queue_family();
        info.Queue = ctx_.queue();
        info.DescriptorPool = ui_pool_;
        info.MinImageCount = std::max(window_.image_count(), 2u);
        info.ImageCount = std::max(window_.image_count(), 2u);
        info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
        ImGui_ImplVulkan_Init(&info, window_.render_pass());
        ctx_.submit_and_wait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
        ImGui_ImplVulkan_DestroyFontUploadObjects();
    }

    gpu::Context& ctx_;
    ViewWindow& window_;
    Scene scene_;
    std::optional<control::PreparedControl> control_;
    SurfaceSettings surface_settings_;
    std::unique_ptr<gpu::ShaderWatcher> watcher_;
    std::unique_ptr<PbfSolver> solver_;
    std::unique_ptr<control::ControlDriver> driver_;
    std::unique_ptr<SurfaceRenderer> surface_;
    std::unique_ptr<MetaballRenderer> metaball_;
    std::unique_ptr<ScreenSpaceRenderer> screen_space_;
    uint32_t render_w_ = 0, render_h_ = 0;
    const gpu::Buffer* last_color_ = nullptr;
    struct BufferDeleter {
        gpu::Context* ctx;
        void operator()(gpu::Buffer* b) const { gpu::destroy_buffer(*ctx, *b); delete b; }
    };
    std::unique_ptr<gpu::Buffer, BufferDeleter> debug_image_{nullptr, BufferDeleter{&ctx_}};
    int view_ = 0;  // index into kViews
    gpu::GpuTimer render_timer_, sim_timer_;
    control::PushForce push_;       // the drag brush
    control::StepForces forces_;    // the control shape's force and the brush, for the solver
    bool timer_pending_ = false;
    std::map<std::string, double> render_passes_, sim_passes_;
    std::deque<float> history_;
    OrbitCamera orbit_;
    std::string method_ = "adaptive";
    std::string status_;
    fs::path screenshot_dir_ = ".";
    uint32_t shots_ = 0;
    bool playing_ = false, step_once_ = false, quit_ = false, failed_ = false;
    bool fly_ = false;  // the right button turns the view about the eye, WASD moves it
    std::vector<fs::path> shape_files_;  // meshes of the active control section, in its order
    char mesh_path_[512] = "assets/meshes/sphere.obj";
    VkDescriptorPool ui_pool_ = VK_NULL_HANDLE;
};

}  // namespace

int cmd_view(const std::vector<std::string>& argv) {
    std::string error;
    const FlagSpec spec =
        with_render_flags({{"--device", "--script", "--record", "--size", "--frames", "--shaders"}, {"--validation", "--play"}});
    auto args = parse_args(argv, spec, "view", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    if (args->positional.size() != 1) {
        std::fprintf(stderr, "aquaform view: give exactly one scene file, e.g. aquaform view assets/scenes/dam_break.json\n");
        return kExitUsage;
    }
    auto loaded = load_scene(args->positional[0]);
    if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
    Scene scene = loaded.value();
    std::optional<control::PreparedControl> control;
    if (scene.control_json) {
        auto prepared = control::prepare_control_scene(scene);
        if (!prepared) return std::fprintf(stderr, "aquaform: %s\n", prepared.error().c_str()), kExitUsage;
        control = std::move(prepared.value());
    }
    auto settings = render_settings_from(*args, &error);
    if (!settings) return std::fprintf(stderr, "aquaform view: %s\n", error.c_str()), kExitUsage;
    std::vector<ViewAction> script;
    if (args->has("--script")) {
        auto loaded_script = load_view_script(args->value("--script"));
        if (!loaded_script) return std::fprintf(stderr, "aquaform view: %s\n", loaded_script.error().c_str()), kExitUsage;
        script = loaded_script.value();
    }
    if (args->has("--play")) script.insert(script.begin(), ViewAction{0, "play", ""});
    uint32_t width = 480, height = 360;
    if (args->has("--size") && !parse_resolution(args->value("--size"), &width, &height))
        return std::fprintf(stderr, "aquaform view: --size must look like 480x360, got \"%s\"\n", args->value("--size").c_str()),
               kExitUsage;
    uint32_t max_frames = 0;
    if (args->has("--frames")) {
        auto f = parse_positive("--frames", args->value("--frames"), &error);
        if (!f) return std::fprintf(stderr, "aquaform view: %s\n", error.c_str()), kExitUsage;
        max_frames = uint32_t(*f);
    }
    const fs::path record_dir = args->value("--record", "");
    if (!record_dir.empty()) {
        std::error_code ec;
        fs::create_directories(record_dir, ec);
        if (ec) return std::fprintf(stderr, "aquaform view: cannot create %s: %s\n", record_dir.string().c_str(), ec.message().c_str()),
                      kExitFailure;
    }

    auto window = ViewWindow::open(int(width), int(height), "aquaform - " + scene.name);
    if (!window) return std::fprintf(stderr, "aquaform view: %s\n", window.error().c_str()), kExitFailure;
    ViewWindow& win = *window.value();
    gpu::ContextOptions options{args->value("--device"), validation_requested(*args)};
    options.instance_extensions = win.instance_extensions();
    options.make_surface = [&win](VkInstance instance) { return win.create_surface(instance); };
    gpu::Context ctx(options);
    win.attach(ctx);
    int status = kExitOk;
    {
        Viewer viewer(ctx, win, scene, std::move(control), *settings);
        viewer.set_screenshot_dir(record_dir.empty() ? fs::path(".") : record_dir);
        // Hot reload watches --shaders DIR, else the source tree's shaders/ beside the build.
        std::error_code ec;
        const fs::path shaders = args->has("--shaders")
                                     ? fs::path(args->value("--shaders"))
                                     : fs::read_symlink("/proc/self/exe", ec).parent_path() / ".." / "shaders";
        if (fs::is_directory(shaders)) viewer.watch_shaders(fs::weakly_canonical(shaders, ec));
        else if (args->has("--shaders"))
            std::fprintf(stderr, "aquaform view: --shaders %s is not a directory; shader hot reload is off\n",
                         shaders.string().c_str());
        status = viewer.run(script, record_dir, max_frames);
    }
    win.detach();  // the swapchain goes before the device
    return exit_status(ctx, status);
}

}  // namespace aquaform::cli
