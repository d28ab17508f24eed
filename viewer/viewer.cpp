// The viewer's window thread: input, panels, the worker's pictures (viewer/viewer.h).
#include "viewer/viewer.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_impl_glfw.h>
#include <imgui_impl_vulkan.h>

#include "core/error.h"
#include "core/interrupt.h"
#include "gpu/context.h"
#include "gpu/staging.h"
#include "gpu/vk_check.h"
#include "pictures/image_io.h"
#include "render/registry.h"
#include "render/wireframe.h"
#include "viewer/view_setup.h"
#include "viewer/view_shapes.h"
#include "viewer/view_window.h"

namespace aquaform::viewer {

namespace {

namespace fs = std::filesystem;

/// Files dropped onto the window since the last frame (GLFW calls back with no user data to
/// spare: the ImGui backend owns the window's callbacks, and there is one viewer per process).
std::vector<std::string> g_dropped;
void on_drop(GLFWwindow*, int count, const char** paths) {
    for (int i = 0; i < count; ++i) g_dropped.emplace_back(paths[i]);
}

class Viewer {
public:
    Viewer(gpu::Context& ctx, ViewWindow& window, session::SessionPlan plan, const ViewerOptions& options)
        : ctx_(ctx),
          window_(window),
          options_(options),
          scene_name_(plan.scene.name),
          domain_(plan.scene.domain),
          spacing_(plan.scene.particle_spacing),
          solver_settings_(plan.scene.solver),
          picture_scale_(options.picture_scale) {
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_.handle(), &w, &h);
        orbit_ = OrbitCamera::around(scene_camera(plan.scene, float(std::max(w, 1)) / float(std::max(h, 1))));
        controls_.surface = options.surface;
        controls_.method = options.method;
        controls_.camera = orbit_.camera();
        controls_.width = uint32_t(std::max(w, 16));
        controls_.height = uint32_t(std::max(h, 16));
        worker_ = std::make_unique<ViewWorker>(ctx_, std::move(plan), controls_, options.watch_shaders);
        worker_->set_lockstep(options.lockstep);
        init_ui();
        glfwSetDropCallback(window_.handle(), on_drop);
    }
    ~Viewer() {
        worker_.reset();  // stops the thread; waits for the queue
        ImGui_ImplVulkan_Shutdown();
        ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext();
        if (ui_pool_) vkDestroyDescriptorPool(ctx_.device(), ui_pool_, nullptr);
    }

    ViewSummary run() {
        const std::vector<ViewAction>& script = options_.script;
        size_t next_action = 0;
        const auto start = std::chrono::steady_clock::now();
        worker_->start();
        worker_->wait(worker_->request_frame());  // the first picture, so that every frame has one
        ViewSummary summary;
        uint32_t frame = 0;
        auto frame_start = std::chrono::steady_clock::now();
        // Ctrl-C in the terminal closes the window as Esc does (the command then exits 130).
        for (; !window_.should_close() && !quit_ && !interrupted() &&
               (options_.max_frames == 0 || frame < options_.max_frames);
             ++frame) {
            glfwPollEvents();
            while (next_action < script.size() && script[next_action].frame <= frame) apply(script[next_action++]);
            for (const std::string& file : std::exchange(g_dropped, {})) drop(file);
            if (quit_) break;
            read_report();
            if (!report_.fatal.empty()) break;
            if (!draw(frame)) continue;
            if (!options_.record_dir.empty()) {
                char name[32];
                std::snprintf(name, sizeof name, "frame_%04u.png", frame);
                screenshot(options_.record_dir / name);
            }
            const auto now = std::chrono::steady_clock::now();
            if (frame > 0)
                summary.longest_frame_ms = std::max(
                    summary.longest_frame_ms, std::chrono::duration<double, std::milli>(now - frame_start).count());
            frame_start = now;
        }
        summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        read_report();
        summary.window_frames = frame;
        summary.report = report_;
        summary.width = controls_.width;
        summary.height = controls_.height;
        summary.method = controls_.method;
        summary.errors = errors_;
        // The script's mesh actions the worker could not do (its frame came and the mesh did not fit).
        summary.errors.insert(summary.errors.end(), report_.refused.begin(), report_.refused.end());
        return summary;
    }

private:
    void read_report() {
        report_ = worker_->report();
        if (report_.blowups != blowups_seen_) {
            blowups_seen_ = report_.blowups;
            playing_ = false;  // the worker holds until the window pauses
        }
        if (report_.status != worker_status_) status_ = worker_status_ = report_.status;
    }

    /// One window frame: hand the controls to the worker, blit its newest picture, UI, present.
    /// False when nothing was drawn (minimised).
    bool draw(uint32_t frame) {
        VkCommandBuffer cmd = window_.begin_frame();
        if (!cmd) return false;
        ImGui_ImplVulkan_NewFrame();
        ImGui_ImplGlfw_NewFrame();
        ImGui::NewFrame();
        handle_input();
        panel(frame);
        const VkExtent2D extent = window_.extent();
        controls_.camera = orbit_.camera();
        controls_.playing = playing_;
        // The picture may be smaller than the window (the blit scales it up): a quicker fluid.
        const PictureSize picture = picture_of_window(extent.width, extent.height, picture_scale_);
        controls_.width = picture.width;
        controls_.height = picture.height;
        worker_->set_controls(controls_);
        if (options_.lockstep) worker_->wait(worker_->request_frame());
        picture_ = worker_->take_picture();
        draw_shapes();
        draw_nozzles();
        ImGui::Render();
        window_.blit(cmd, *picture_.rgba, picture_.width, picture_.height);
        window_.begin_ui(cmd);
        ImGui_ImplVulkan_RenderDrawData(ImGui::GetDrawData(), cmd);
        window_.end_ui(cmd);
        window_.end_frame(cmd);
        return true;
    }

    /// The active shapes' edges over the picture, silhouettes solid and the rest faint.
    void draw_shapes() {
        if (!report_.shapes || !show_shapes_) return;
        const ImGuiIO& io = ImGui::GetIO();
        ImDrawList* draw = ImGui::GetBackgroundDrawList();
        const uint32_t w = uint32_t(std::max(io.DisplaySize.x, 1.0f)), h = uint32_t(std::max(io.DisplaySize.y, 1.0f));
        for (const geometry::Mesh& mesh : *report_.shapes)
            for (const WireEdge& e : project_wireframe(mesh.vertices, mesh.faces, controls_.camera, w, h))
                draw->AddLine(ImVec2(e.a.x + 0.5f, e.a.y + 0.5f), ImVec2(e.b.x + 0.5f, e.b.y + 0.5f),
                              e.silhouette ? IM_COL32(255, 140, 40, 230) : IM_COL32(255, 140, 40, 50));
    }

    /// Each nozzle over the picture: a ring where it stands and a line 5 cm along its aim, the
    /// selected one bright (the window's overlay, not in screenshots).
    void draw_nozzles() {
        if (report_.nozzles.empty()) return;
        const ImGuiIO& io = ImGui::GetIO();
        const glm::vec2 size(std::max(io.DisplaySize.x, 1.0f), std::max(io.DisplaySize.y, 1.0f));
        const CameraBlock view = camera_block(controls_.camera, uint32_t(size.x), uint32_t(size.y));
        const auto on_screen = [&](const glm::vec3& p) -> std::optional<ImVec2> {
            const glm::vec3 rel = p - glm::vec3(view.eye);
            const float z = glm::dot(rel, glm::vec3(view.forward));
            if (!(z > 1e-4f)) return std::nullopt;  // behind the eye
            const float u = glm::dot(rel, glm::vec3(view.right)) / (z * view.forward.w);
            const float v = -glm::dot(rel, glm::vec3(view.up)) / (z * view.right.w);
            return ImVec2(0.5f * (u + 1.0f) * size.x, 0.5f * (v + 1.0f) * size.y);
        };
        ImDrawList* draw = ImGui::GetBackgroundDrawList();
        for (size_t i = 0; i < report_.nozzles.size(); ++i) {
            const NozzleView& n = report_.nozzles[i];
            const auto at = on_screen(n.position), to = on_screen(n.position + 0.05f * n.direction);
            if (!at) continue;
            const bool selected = int(i) == nozzle_;
            const ImU32 colour = n.open ? IM_COL32(80, 200, 255, selected ? 255 : 120) : IM_COL32(160, 160, 160, 160);
            draw->AddCircle(*at, selected ? 7.0f : 5.0f, colour, 16, 2.0f);
            if (to) draw->AddLine(*at, *to, colour, 2.0f);
        }
    }

    /// The picture the window shows (without the UI) as PNG.
    void screenshot(const fs::path& path) {
        if (!picture_.rgba) return;
        Image image;
        image.width = picture_.width;
        image.height = picture_.height;
        image.rgba.resize(size_t(image.width) * image.height * 4);
        gpu::download(ctx_, *picture_.rgba, image.rgba.data(), image.rgba.size());
        std::error_code ec;
        if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
        auto written = write_png(path, image);
        if (!written) {
            errors_.push_back(written.error());
        } else {
            status_ = "saved " + path.string();
        }
    }

    // ---- interaction ------------------------------------------------------------------------

    void post(ViewOp op, const fs::path& file = {}, std::optional<glm::vec3> at = std::nullopt) {
        worker_->post({op, file, solver_settings_, at});
    }

    /// Moves, aims, shuts or opens a nozzle of the scene (`script`: the action's where(), or
    /// empty for the window's own).
    void post_nozzle(const std::string& name, const session::SimulationSession::NozzleChange& change,
                     const std::string& script = {}) {
        ViewCommand c{ViewOp::nozzle};
        c.solver = solver_settings_;
        c.nozzle = name;
        c.nozzle_change = change;
        c.script = script;
        worker_->post(std::move(c));
    }

    /// The nozzle the panel has selected, as the worker last reported it (nothing without emitters).
    const NozzleView* selected_nozzle() const {
        if (report_.nozzles.empty()) return nullptr;
        return &report_.nozzles[size_t(std::clamp(nozzle_, 0, int(report_.nozzles.size()) - 1))];
    }

    /// Ctrl + left click places the selected nozzle under the cursor (at its height), Ctrl +
    /// right click aims it at the point under the cursor. True when the click was the nozzle's.
    bool nozzle_click(const ImGuiIO& io) {
        const NozzleView* n = selected_nozzle();
        if (!n || !io.KeyCtrl) return false;
        const bool place = ImGui::IsMouseClicked(ImGuiMouseButton_Left),
                   aim = ImGui::IsMouseClicked(ImGuiMouseButton_Right);
        if (!place && !aim)
            return ImGui::IsMouseDown(ImGuiMouseButton_Left) || ImGui::IsMouseDown(ImGuiMouseButton_Right);
        const glm::vec2 size(std::max(io.DisplaySize.x, 1.0f), std::max(io.DisplaySize.y, 1.0f));
        const glm::vec2 ndc = 2.0f * glm::vec2(io.MousePos.x, io.MousePos.y) / size - 1.0f;
        session::SimulationSession::NozzleChange change;
        if (place)
            change.position = nozzle_place_under_cursor(orbit_.camera(), domain_, ndc, size.x / size.y, n->position);
        if (aim) change.direction = nozzle_aim_under_cursor(orbit_.camera(), ndc, size.x / size.y, n->position);
        if (change.position || change.direction) post_nozzle(n->name, change);
        return true;
    }
    /// A script's action on the worker: one it cannot do makes the command exit 1.
    void post(ViewOp op, const ViewAction& a) {
        worker_->post({op, a.value, solver_settings_, std::nullopt, a.where()});
    }

    /// A mesh dropped on the window becomes the shape, standing where the cursor points; with
    /// Shift held it becomes a still obstacle there instead.
    void drop(const fs::path& file) {
        const bool as_obstacle = glfwGetKey(window_.handle(), GLFW_KEY_LEFT_SHIFT) == GLFW_PRESS ||
                                 glfwGetKey(window_.handle(), GLFW_KEY_RIGHT_SHIFT) == GLFW_PRESS;
        double x = 0.0, y = 0.0;
        int w = 1, h = 1;
        glfwGetCursorPos(window_.handle(), &x, &y);
        glfwGetWindowSize(window_.handle(), &w, &h);
        const glm::vec2 ndc(2.0f * float(x) / float(std::max(w, 1)) - 1.0f,
                            2.0f * float(y) / float(std::max(h, 1)) - 1.0f);
        post(as_obstacle ? ViewOp::obstacle : ViewOp::attach, file,
             point_under_cursor(orbit_.camera(), domain_, ndc, float(w) / float(std::max(h, 1))));
    }

    void apply(const ViewAction& a) {
        if (a.what == "play")
            playing_ = true;
        else if (a.what == "pause")
            playing_ = false;
        else if (a.what == "step")
            post(ViewOp::step);
        else if (a.what == "reset")
            post(ViewOp::reset);
        else if (a.what == "quit") {
            worker_->wait(worker_->request_frame());  // a script's actions all take effect first
            quit_ = true;
        } else if (a.what == "screenshot")
            screenshot(fs::path(a.value).is_absolute() ? fs::path(a.value) : options_.screenshot_dir / a.value);
        else if (a.what == "method")
            set_method_checked(a.value);
        else if (a.what == "attach")
            post(ViewOp::attach, a);
        else if (a.what == "union")
            post(ViewOp::union_with, a);
        else if (a.what == "morph")
            post(ViewOp::morph, a);
        else if (a.what == "view")
            set_view_checked(a.value);
        else if (a.what == "release")
            post(ViewOp::release);
        else if (a.what == "obstacle")
            post(ViewOp::obstacle, a);
        else if (a.what == "remove_obstacles")
            post(ViewOp::remove_obstacles);
        else if (a.what == "resize")
            resize(a.value);
        else if (a.what == "whitewater")
            controls_.show_whitewater = a.value == "on";
        else if (a.what == "nozzle")
            post_nozzle(a.value, {a.position, a.direction, a.open}, a.where());
        else if (a.what == "solver") {
            solver_settings_.method = a.value == "dfsph" ? PressureMethod::dfsph : PressureMethod::pbf;
            post(ViewOp::solver);
        } else if (a.what == "iterations" || a.what == "substeps") {
            (a.what == "iterations" ? solver_settings_.iterations : solver_settings_.substeps) =
                uint32_t(std::stoul(a.value));
            post(ViewOp::solver);
        }
    }

    /// Sets the window's size (a script's resize; the swapchain and the pictures follow).
    void resize(const std::string& size) {
        uint32_t w = 0, h = 0;
        if (!parse_resolution(size, &w, &h)) return;  // checked when the script was read
        glfwSetWindowSize(window_.handle(), int(w), int(h));
        // Wait until the window system has applied it, so that this frame already uses it.
        for (int i = 0; i < 100; ++i) {
            int fw = 0, fh = 0;
            glfwPollEvents();
            glfwGetFramebufferSize(window_.handle(), &fw, &fh);
            if (uint32_t(fw) == w && uint32_t(fh) == h) break;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    }

    void set_view_checked(const std::string& name) {
        const auto it = std::find(std::begin(kDebugViewNames), std::end(kDebugViewNames), name);
        if (it == std::end(kDebugViewNames)) {
            errors_.push_back("unknown view \"" + name +
                              "\" in the script; use image, steps, classification, tiles, "
                              "depth_all or depth_agg");
            return;
        }
        controls_.view = int(it - std::begin(kDebugViewNames));
    }

    void set_method_checked(const std::string& method) {
        if (std::find(view_methods().begin(), view_methods().end(), method) == view_methods().end()) {
            errors_.push_back("unknown method \"" + method + "\" in the script; use one of the method menu's");
            return;
        }
        controls_.method = method;
    }

    /// Left drag pushes the fluid near the mouse ray along the drag; right drag orbits, middle
    /// drag pans, the wheel zooms; with Ctrl held, clicks place and aim the selected nozzle.
    void handle_input() {
        ImGuiIO& io = ImGui::GetIO();
        if (!io.WantCaptureMouse && !nozzle_click(io)) {
            const ViewCamera camera = orbit_.camera();
            const glm::mat3 axes = camera_axes(camera);
            // World metres per pixel at the orbit's target.
            const float metres_per_px =
                2.0f * orbit_.distance * std::tan(glm::radians(orbit_.fov) * 0.5f) / std::max(io.DisplaySize.y, 1.0f);
            if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
                const CameraBlock view = camera_block(camera, uint32_t(std::max(io.DisplaySize.x, 1.0f)),
                                                      uint32_t(std::max(io.DisplaySize.y, 1.0f)));
                const float u = 2.0f * io.MousePos.x / std::max(io.DisplaySize.x, 1.0f) - 1.0f;
                const float v = 2.0f * io.MousePos.y / std::max(io.DisplaySize.y, 1.0f) - 1.0f;
                const glm::vec3 dir =
                    glm::normalize(glm::vec3(view.forward) + u * view.forward.w * glm::vec3(view.right) -
                                   v * view.right.w * glm::vec3(view.up));
                const glm::vec3 drag = (io.MouseDelta.x * axes[0] - io.MouseDelta.y * axes[1]) * metres_per_px;
                // A drag of one centimetre per simulated frame accelerates the fluid at about 1 g
                // (the worker adds up the strokes of the window frames between two of its frames).
                PushStroke stroke;
                stroke.origin = camera.eye;
                stroke.dir = dir;
                stroke.accel = drag * 1000.0f;
                stroke.radius = std::max(4.0f * spacing_, 0.05f * orbit_.distance);
                if (glm::length(stroke.accel) > 0.0f) worker_->add_stroke(stroke);
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
                const float speed = 0.5f * glm::length(domain_.max - domain_.min) * io.DeltaTime;
                const std::pair<int, glm::vec3> moves[] = {{GLFW_KEY_W, axes[2]}, {GLFW_KEY_S, -axes[2]},
                                                           {GLFW_KEY_D, axes[0]}, {GLFW_KEY_A, -axes[0]},
                                                           {GLFW_KEY_E, axes[1]}, {GLFW_KEY_Q, -axes[1]}};
                for (const auto& [key, axis] : moves)
                    if (ImGui::IsKeyDown(key)) orbit_.target += speed * axis;
            }
            if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) playing_ = !playing_;
            if (ImGui::IsKeyPressed(GLFW_KEY_N)) post(ViewOp::step);
            if (ImGui::IsKeyPressed(GLFW_KEY_R)) post(ViewOp::reset);
            if (ImGui::IsKeyPressed(GLFW_KEY_P))
                screenshot(options_.screenshot_dir / ("screenshot_" + std::to_string(shots_++) + ".png"));
            if (ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) quit_ = true;
        }
    }

    void panel(uint32_t frame) {
        ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
        ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
        ImGui::Begin("aquaform");
        ImGui::Text("%s: %u particles, t = %.3f s", scene_name_.c_str(), report_.particles, report_.sim_time);
        ImGui::Text("frame %u: window %.1f frames/s", frame, ImGui::GetIO().Framerate);
        ImGui::Text("fluid: %.2f pictures/s (%llu made)", report_.frames_per_s, (unsigned long long)report_.frames);
        if (const auto& w = report_.whitewater) {
            ImGui::Checkbox("whitewater", &controls_.show_whitewater);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("draw the spray, foam and bubbles (they are made either way)");
            ImGui::SameLine();
            ImGui::Text("%u spray, %u foam, %u bubbles", w->spray, w->foam, w->bubbles);
        }
        if (ImGui::Button(playing_ ? "Pause" : "Play")) playing_ = !playing_;
        ImGui::SameLine();
        if (ImGui::Button("Step")) post(ViewOp::step);
        ImGui::SameLine();
        if (ImGui::Button("Reset")) post(ViewOp::reset);
        ImGui::SliderFloat("picture scale", &picture_scale_, 0.25f, 1.0f, "%.2f");
        if (ImGui::IsItemHovered())
            ImGui::SetTooltip("the fluid's picture against the window's size: smaller is quicker");
        if (ImGui::BeginCombo("method", controls_.method.c_str())) {
            for (const std::string& m : view_methods())
                if (ImGui::Selectable(m.c_str(), controls_.method == m)) controls_.method = m;
            ImGui::EndCombo();
        }
        if (ImGui::CollapsingHeader("Solver", ImGuiTreeNodeFlags_DefaultOpen)) {
            // Applied when a slider is let go: the solver is made again from the current particles.
            SolverSettings& s = solver_settings_;
            int iterations = int(s.iterations), substeps = int(s.substeps);
            bool released = false;
            int method = s.method == PressureMethod::dfsph ? 1 : 0;
            released |= ImGui::Combo("pressure", &method, "pbf (fast)\0dfsph (experimental)\0");
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("the pressure solve: position-based fluids, or divergence-free SPH (docs/solver.md)");
            s.method = method == 1 ? PressureMethod::dfsph : PressureMethod::pbf;
            ImGui::SliderInt("iterations", &iterations, 1, 16);
            released |= ImGui::IsItemDeactivatedAfterEdit();
            ImGui::SliderInt("substeps", &substeps, 1, 16);
            released |= ImGui::IsItemDeactivatedAfterEdit();
            ImGui::SliderFloat("viscosity", &s.viscosity, 0.0f, 0.2f);
            released |= ImGui::IsItemDeactivatedAfterEdit();
            ImGui::SliderFloat("vorticity", &s.vorticity, 0.0f, 0.01f, "%.4f");
            released |= ImGui::IsItemDeactivatedAfterEdit();
            s.iterations = uint32_t(iterations);
            s.substeps = uint32_t(substeps);
            if (released) post(ViewOp::solver);
        }
        if (ImGui::CollapsingHeader("Shape", ImGuiTreeNodeFlags_DefaultOpen)) {
            const bool has_shape = !report_.shape_files.empty();
            ImGui::InputText("mesh", mesh_path_, sizeof mesh_path_);
            if (ImGui::Button("Attach")) post(ViewOp::attach, mesh_path_);
            ImGui::SameLine();
            if (ImGui::Button("Union") && has_shape) post(ViewOp::union_with, mesh_path_);
            ImGui::SameLine();
            if (ImGui::Button("Morph") && has_shape) post(ViewOp::morph, mesh_path_);
            ImGui::SameLine();
            if (ImGui::Button("Release")) post(ViewOp::release);
            if (ImGui::Button("Obstacle")) post(ViewOp::obstacle, mesh_path_);
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip("the mesh as a still solid in the flow (or drop an OBJ with Shift held)");
            ImGui::SameLine();
            if (ImGui::Button("Remove obstacles")) post(ViewOp::remove_obstacles);
            ImGui::Checkbox("show shapes", &show_shapes_);
            if (has_shape)
                for (const fs::path& f : report_.shape_files) ImGui::BulletText("%s", f.filename().string().c_str());
            else
                ImGui::TextDisabled("no shape: type a mesh path or drop an OBJ on the window (Shift: as an obstacle)");
        }
        if (!report_.nozzles.empty() && ImGui::CollapsingHeader("Nozzles", ImGuiTreeNodeFlags_DefaultOpen)) {
            for (size_t i = 0; i < report_.nozzles.size(); ++i) {
                const NozzleView& n = report_.nozzles[i];
                if (ImGui::RadioButton(n.name.c_str(), nozzle_ == int(i))) nozzle_ = int(i);
                ImGui::SameLine();
                bool open = n.open;
                if (ImGui::Checkbox(("open##" + n.name).c_str(), &open)) post_nozzle(n.name, {{}, {}, open});
                ImGui::SameLine();
                ImGui::TextDisabled("(%.2f, %.2f, %.2f)", n.position.x, n.position.y, n.position.z);
            }
            // The panel is narrow: the long form is in docs/viewer.md and the tooltip.
            ImGui::TextDisabled("Ctrl+left click: place, Ctrl+right: aim");
            if (ImGui::IsItemHovered())
                ImGui::SetTooltip(
                    "Ctrl + left click places the selected nozzle under the cursor, at its height;\n"
                    "Ctrl + right click aims it at the point under the cursor");
        }
        if ((controls_.method == "adaptive" || controls_.method == "uniform") && ImGui::CollapsingHeader("Renderer")) {
            SurfaceSettings& r = controls_.surface;
            const SurfaceSettings before = r;
            ImGui::Combo("view", &controls_.view, kDebugViews, IM_ARRAYSIZE(kDebugViews));
            ImGui::Checkbox("mask", &r.use_mask);
            ImGui::SameLine();
            ImGui::Checkbox("skip", &r.use_skip);
            ImGui::SameLine();
            ImGui::Checkbox("adaptive res.", &r.adaptive_resolution);
            ImGui::Checkbox("blend normals", &r.blend_normals);
            ImGui::SameLine();
            ImGui::Checkbox("anisotropic", &r.anisotropic);
            bool stretched = r.surface == SurfaceKernel::anisotropic;
            if (ImGui::Checkbox("anisotropic surface (Yu & Turk)", &stretched))
                r.surface = stretched ? SurfaceKernel::anisotropic : SurfaceKernel::isotropic;
            ImGui::SliderFloat("spray whiteness", &r.spray_whiteness, 0.0f, 1.0f);
            ImGui::SliderFloat("iso (lone radius)", &r.lone_radius, 0.2f, 3.0f);
            ImGui::SliderFloat("step [radii]", &r.step_radii, 0.1f, 4.0f);
            bool wu_mask = !r.tight_mask;
            if (ImGui::Checkbox("Wu's mask (counts x W(0), weights a, b)", &wu_mask)) r.tight_mask = !wu_mask;
            ImGui::SliderFloat("mask a", &r.mask_a, 0.05f, 1.0f);
            ImGui::SliderFloat("mask b", &r.mask_b, 0.05f, 1.0f);
            ImGui::SliderFloat("eps1 [radii^2]", &r.tile_eps1, 0.0f, 16.0f);
            ImGui::SliderFloat("eps2 [radii^2]", &r.tile_eps2, 0.1f, 64.0f);
            ImGui::SliderFloat("blend A", &r.blend_a, 0.0f, 1.0f);
            ImGui::SliderFloat("normal smoothing [deg]", &r.normal_smoothing_deg, 0.0f, 90.0f);
            ImGui::SliderFloat("blend B", &r.blend_b, -0.5f, 0.5f);
            bool wu_skip = !r.exact_skip;
            if (ImGui::Checkbox("Wu's skip (after maxSkipCounts; can jump over splashes)", &wu_skip))
                r.exact_skip = !wu_skip;
            int skip = int(r.max_skip_evals);
            if (ImGui::SliderInt("maxSkipCounts", &skip, 1, 64)) r.max_skip_evals = uint32_t(skip);
            if (auto valid = validate(r); !valid) {
                status_ = valid.error();
                r = before;  // keep the last settings the renderer accepts
            }
        }
        if (ImGui::CollapsingHeader("GPU time", ImGuiTreeNodeFlags_DefaultOpen)) {
            // The last pictures' GPU time: the render total and the simulation large, each render
            // pass as a line of its own with its latest figure.
            auto chart = [&](const std::string& name, const char* label, float height) {
                const auto it = report_.history.find(name);
                if (it == report_.history.end() || it->second.empty()) return;
                const std::vector<float> h(it->second.begin(), it->second.end());
                char overlay[64];
                std::snprintf(overlay, sizeof overlay, "%.1f ms", h.back());
                ImGui::PlotLines(label, h.data(), int(h.size()), 0, overlay, 0.0f, FLT_MAX, ImVec2(0, height));
            };
            chart("render", "render", 48.0f);
            chart("simulation", "simulation", 48.0f);
            for (const auto& [name, ms] : report_.render_ms) {
                const std::string label =
                    name.rfind("render_", 0) == 0 ? name.substr(7) : name;  // "render_march": "march"
                chart(name, label.c_str(), 18.0f);
            }
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
    ViewerOptions options_;
    std::string scene_name_;
    Box domain_;
    float spacing_;
    SolverSettings solver_settings_;  // what the Solver sliders show; sent when one is let go
    float picture_scale_;             // the picture's size against the window's (a slider)
    std::unique_ptr<ViewWorker> worker_;
    ViewControls controls_;
    ViewReport report_;
    ViewWorker::Picture picture_;
    uint32_t blowups_seen_ = 0;
    std::string worker_status_;
    OrbitCamera orbit_;
    std::string status_;
    uint32_t shots_ = 0;
    std::vector<std::string> errors_;
    bool playing_ = false, quit_ = false;
    bool fly_ = false;  // the right button turns the view about the eye, WASD moves it
    bool show_shapes_ = true;
    char mesh_path_[512] = "assets/meshes/sphere.obj";
    int nozzle_ = 0;  // the nozzle panel's selection
    VkDescriptorPool ui_pool_ = VK_NULL_HANDLE;
};

}  // namespace

ViewSummary run_viewer(gpu::Context& ctx, ViewWindow& window, session::SessionPlan plan, const ViewerOptions& options) {
    // What the script's mesh actions do to this scene, before the session is made: bad input.
    std::vector<fs::path> shapes;
    if (plan.control)
        for (const control::ControlMesh& m : plan.control->section.meshes)
            if (!m.file.empty()) shapes.push_back(m.file);
    if (auto checked = check_script_actions(options.script, plan.scene, shapes); !checked)
        throw Failure(checked.error());
    Viewer viewer(ctx, window, std::move(plan), options);
    return viewer.run();
}

bool run_viewer_printed(gpu::Context& ctx, ViewWindow& window, session::SessionPlan plan, const ViewerOptions& options,
                        const std::string& scene_name) {
    std::printf("viewing %s: %llu particles on %s; Esc in the window (or Ctrl-C here) quits\n", scene_name.c_str(),
                (unsigned long long)plan.scene.particle_count(), ctx.info().name.c_str());
    std::fflush(stdout);
    const ViewSummary run = run_viewer(ctx, window, std::move(plan), options);
    const ViewReport& report = run.report;
    const double s = run.seconds > 0.0 ? run.seconds : 1.0;
    std::printf(
        "aquaform view: %u window frames in %.1f s (%.2f frames/s, the longest %.0f ms); %llu pictures of the fluid "
        "(%.2f/s; %u particles, %ux%u, %s)\n",
        run.window_frames, run.seconds, run.window_frames / s, run.longest_frame_ms, (unsigned long long)report.frames,
        report.frames / s, report.particles, run.width, run.height, run.method.c_str());
    for (const std::string& e : run.errors) std::fprintf(stderr, "aquaform view: %s\n", e.c_str());
    if (!report.fatal.empty())
        std::fprintf(stderr, "aquaform view: the simulation stopped: %s\n", report.fatal.c_str());
    if (!report.blowup.empty()) std::fprintf(stderr, "aquaform view: %s\n", report.blowup.c_str());
    return run.errors.empty() && report.fatal.empty() && report.blowup.empty();
}

}  // namespace aquaform::viewer
