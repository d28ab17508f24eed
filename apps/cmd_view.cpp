// `aquaform view SCENE`: the interactive viewer. A GLFW window presents the fluid's pictures
// straight from the GPU (apps/view_window.h); the simulation and the renderers run on a worker
// thread (apps/view_worker.h), so the window keeps drawing its panels while a frame of the fluid
// is made. Dear ImGui panels play, pause, step and reset the simulation, switch the surface method
// and change solver settings, and chart the GPU time per pass; an OBJ dropped on the window becomes
// the shape the fluid fills (Release lets it go), and the active shapes are drawn as wireframes.
// Dragging with the left button pushes the fluid; the right button orbits, the middle pans and the
// wheel zooms the camera; F switches to a fly camera (right button looks around, W/A/S/D/Q/E move).
// Keys: space play/pause, N one step, R reset, P screenshot, Esc quit. --script plays UI actions
// at given frames (apps/view_script.h); --record DIR writes every frame drawn; both step the window
// with the fluid (one picture per window frame) so that frame numbers mean the same every run.
// Shaders edited while it runs are recompiled and reloaded (gpu/shader_compiler.h).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
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

#include "study/bench_scenes.h"
#include "apps/cli.h"
#include "apps/render_options.h"
#include "apps/view_script.h"
#include "apps/view_shapes.h"
#include "apps/view_window.h"
#include "apps/view_worker.h"
#include "gpu/context.h"
#include "gpu/vk_check.h"
#include "render/surface_settings.h"
#include "render/image_io.h"
#include "render/wireframe.h"

namespace aquaform::cli {

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
    /// `lockstep`: every window frame waits for a picture of the fluid made after that frame's
    /// actions (scripts, recordings); otherwise the window never waits for the worker.
    Viewer(gpu::Context& ctx, ViewWindow& window, session::SessionPlan plan, SurfaceSettings surface_settings,
           const std::string& method, const fs::path& watch_shaders, bool lockstep)
        : ctx_(ctx), window_(window), scene_name_(plan.scene.name), domain_(plan.scene.domain),
          spacing_(plan.scene.particle_spacing), solver_settings_(plan.scene.solver), lockstep_(lockstep) {
        int w = 0, h = 0;
        glfwGetFramebufferSize(window_.handle(), &w, &h);
        orbit_ = OrbitCamera::around(camera_for_domain(domain_, float(std::max(w, 1)) / float(std::max(h, 1))));
        controls_.surface = surface_settings;
        controls_.method = method;
        controls_.camera = orbit_.camera();
        controls_.width = uint32_t(std::max(w, 16));
        controls_.height = uint32_t(std::max(h, 16));
        worker_ = std::make_unique<ViewWorker>(ctx_, std::move(plan), controls_, watch_shaders);
        worker_->set_lockstep(lockstep_);
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

    int run(const std::vector<ViewAction>& script, const fs::path& record_dir, uint32_t max_frames) {
        size_t next_action = 0;
        const auto start = std::chrono::steady_clock::now();
        worker_->start();
        worker_->wait(worker_->request_frame());  // the first picture, so that every frame has one
        uint32_t frame = 0;
        double longest_ms = 0.0;  // the slowest window frame: what the user waits for at worst
        auto frame_start = std::chrono::steady_clock::now();
        for (; !window_.should_close() && !quit_ && (max_frames == 0 || frame < max_frames); ++frame) {
            glfwPollEvents();
            while (next_action < script.size() && script[next_action].frame <= frame) apply(script[next_action++]);
            for (const std::string& file : std::exchange(g_dropped, {})) drop(file);
            if (quit_) break;
            read_report();
            if (!report_.fatal.empty()) break;
            if (!draw(frame)) continue;
            if (!record_dir.empty()) {
                char name[32];
                std::snprintf(name, sizeof name, "frame_%04u.png", frame);
                screenshot(record_dir / name);
            }
            const auto now = std::chrono::steady_clock::now();
            if (frame > 0) longest_ms = std::max(longest_ms, std::chrono::duration<double, std::milli>(now - frame_start).count());
            frame_start = now;
        }
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        read_report();
        std::printf("aquaform view: %u window frames in %.1f s (%.2f frames/s, the longest %.0f ms); %llu pictures of the fluid "
                    "(%.2f/s; %u particles, %ux%u, %s)\n",
                    frame, seconds, seconds > 0 ? frame / seconds : 0.0, longest_ms, (unsigned long long)report_.frames,
                    seconds > 0 ? report_.frames / seconds : 0.0, report_.particles, controls_.width, controls_.height,
                    controls_.method.c_str());
        if (!report_.fatal.empty()) {
            std::fprintf(stderr, "aquaform view: the simulation stopped: %s\n", report_.fatal.c_str());
            return kExitFailure;
        }
        return failed_ ? kExitFailure : kExitOk;
    }

    void set_screenshot_dir(const fs::path& dir) { screenshot_dir_ = dir; }
    void set_picture_scale(float scale) { picture_scale_ = scale; }

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
        controls_.width = std::max(uint32_t(std::lround(float(extent.width) * picture_scale_)), 16u);
        controls_.height = std::max(uint32_t(std::lround(float(extent.height) * picture_scale_)), 16u);
        worker_->set_controls(controls_);
        if (lockstep_) worker_->wait(worker_->request_frame());
        picture_ = worker_->take_picture();
        draw_shapes();
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
        for (const control::Mesh& mesh : *report_.shapes)
            for (const WireEdge& e : project_wireframe(mesh.vertices, mesh.faces, controls_.camera, w, h))
                draw->AddLine(ImVec2(e.a.x + 0.5f, e.a.y + 0.5f), ImVec2(e.b.x + 0.5f, e.b.y + 0.5f),
                              e.silhouette ? IM_COL32(255, 140, 40, 230) : IM_COL32(255, 140, 40, 50));
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
            std::fprintf(stderr, "aquaform view: %s\n", written.error().c_str());
            failed_ = true;
        } else {
            status_ = "saved " + path.string();
        }
    }

    // ---- interaction ------------------------------------------------------------------------

    void post(ViewOp op, const fs::path& file = {}, std::optional<glm::vec3> at = std::nullopt) {
        worker_->post({op, file, solver_settings_, at});
    }

    /// A mesh dropped on the window becomes the shape, standing where the cursor points.
    void drop(const fs::path& file) {
        double x = 0.0, y = 0.0;
        int w = 1, h = 1;
        glfwGetCursorPos(window_.handle(), &x, &y);
        glfwGetWindowSize(window_.handle(), &w, &h);
        const glm::vec2 ndc(2.0f * float(x) / float(std::max(w, 1)) - 1.0f, 2.0f * float(y) / float(std::max(h, 1)) - 1.0f);
        post(ViewOp::attach, file, point_under_cursor(orbit_.camera(), domain_, ndc, float(w) / float(std::max(h, 1))));
    }

    void apply(const ViewAction& a) {
        if (a.what == "play") playing_ = true;
        else if (a.what == "pause") playing_ = false;
        else if (a.what == "step") post(ViewOp::step);
        else if (a.what == "reset") post(ViewOp::reset);
        else if (a.what == "quit") {
            worker_->wait(worker_->request_frame());  // a script's actions all take effect first
            quit_ = true;
        }
        else if (a.what == "screenshot") screenshot(fs::path(a.value).is_absolute() ? fs::path(a.value) : screenshot_dir_ / a.value);
        else if (a.what == "method") set_method_checked(a.value);
        else if (a.what == "attach") post(ViewOp::attach, a.value);
        else if (a.what == "union") post(ViewOp::union_with, a.value);
        else if (a.what == "morph") post(ViewOp::morph, a.value);
        else if (a.what == "view") set_view_checked(a.value);
        else if (a.what == "release") post(ViewOp::release);
        else if (a.what == "resize") resize(a.value);
        else if (a.what == "iterations" || a.what == "substeps") {
            (a.what == "iterations" ? solver_settings_.iterations : solver_settings_.substeps) = uint32_t(std::stoul(a.value));
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
            std::fprintf(stderr, "aquaform view: unknown view \"%s\" in the script; use image, steps, classification, "
                                 "tiles, depth_all or depth_agg\n", name.c_str());
            failed_ = true;
            return;
        }
        controls_.view = int(it - std::begin(kDebugViewNames));
    }

    void set_method_checked(const std::string& method) {
        if (std::find(view_methods().begin(), view_methods().end(), method) == view_methods().end()) {
            std::fprintf(stderr, "aquaform view: unknown method \"%s\" in the script; use one of the method menu's\n",
                         method.c_str());
            failed_ = true;
            return;
        }
        controls_.method = method;
    }

    /// Left drag pushes the fluid near the mouse ray along the drag; right drag orbits, middle
    /// drag pans, the wheel zooms.
    void handle_input() {
        ImGuiIO& io = ImGui::GetIO();
        if (!io.WantCaptureMouse) {
            const ViewCamera camera = orbit_.camera();
            const glm::mat3 axes = camera_axes(camera);
            // World metres per pixel at the orbit's target.
            const float metres_per_px = 2.0f * orbit_.distance * std::tan(glm::radians(orbit_.fov) * 0.5f) /
                                        std::max(io.DisplaySize.y, 1.0f);
            if (ImGui::IsMouseDragging(ImGuiMouseButton_Left)) {
                const CameraBlock view = camera_block(camera, uint32_t(std::max(io.DisplaySize.x, 1.0f)),
                                                      uint32_t(std::max(io.DisplaySize.y, 1.0f)));
                const float u = 2.0f * io.MousePos.x / std::max(io.DisplaySize.x, 1.0f) - 1.0f;
                const float v = 2.0f * io.MousePos.y / std::max(io.DisplaySize.y, 1.0f) - 1.0f;
                const glm::vec3 dir = glm::normalize(glm::vec3(view.forward) + u * view.forward.w * glm::vec3(view.right) -
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
                const std::pair<int, glm::vec3> moves[] = {{GLFW_KEY_W, axes[2]}, {GLFW_KEY_S, -axes[2]}, {GLFW_KEY_D, axes[0]},
                                                           {GLFW_KEY_A, -axes[0]}, {GLFW_KEY_E, axes[1]}, {GLFW_KEY_Q, -axes[1]}};
                for (const auto& [key, axis] : moves)
                    if (ImGui::IsKeyDown(key)) orbit_.target += speed * axis;
            }
            if (ImGui::IsKeyPressed(GLFW_KEY_SPACE)) playing_ = !playing_;
            if (ImGui::IsKeyPressed(GLFW_KEY_N)) post(ViewOp::step);
            if (ImGui::IsKeyPressed(GLFW_KEY_R)) post(ViewOp::reset);
            if (ImGui::IsKeyPressed(GLFW_KEY_P)) screenshot(screenshot_dir_ / ("screenshot_" + std::to_string(shots_++) + ".png"));
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
        if (ImGui::Button(playing_ ? "Pause" : "Play")) playing_ = !playing_;
        ImGui::SameLine();
        if (ImGui::Button("Step")) post(ViewOp::step);
        ImGui::SameLine();
        if (ImGui::Button("Reset")) post(ViewOp::reset);
        ImGui::SliderFloat("picture scale", &picture_scale_, 0.25f, 1.0f, "%.2f");
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("the fluid's picture against the window's size: smaller is quicker");
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
            ImGui::Checkbox("show shapes", &show_shapes_);
            if (has_shape)
                for (const fs::path& f : report_.shape_files) ImGui::BulletText("%s", f.filename().string().c_str());
            else
                ImGui::TextDisabled("no shape: type a mesh path or drop an OBJ on the window");
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
                const std::string label = name.rfind("render_", 0) == 0 ? name.substr(7) : name;  // "render_march": "march"
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
    std::string scene_name_;
    Box domain_;
    float spacing_;
    SolverSettings solver_settings_;  // what the Solver sliders show; sent when one is let go
    bool lockstep_;
    std::unique_ptr<ViewWorker> worker_;
    ViewControls controls_;
    ViewReport report_;
    ViewWorker::Picture picture_;
    uint32_t blowups_seen_ = 0;
    std::string worker_status_;
    OrbitCamera orbit_;
    std::string status_;
    fs::path screenshot_dir_ = ".";
    uint32_t shots_ = 0;
    bool playing_ = false, quit_ = false, failed_ = false;
    bool fly_ = false;  // the right button turns the view about the eye, WASD moves it
    bool show_shapes_ = true;
    float picture_scale_ = 1.0f;  // the picture's size against the window's
    char mesh_path_[512] = "assets/meshes/sphere.obj";
    VkDescriptorPool ui_pool_ = VK_NULL_HANDLE;
};

}  // namespace

int cmd_view(const std::vector<std::string>& argv) {
    std::string error;
    const FlagSpec spec =
        with_render_flags({{"--device", "--script", "--record", "--size", "--frames", "--shaders", "--particles", "--scale"}, {"--validation", "--play", "--async"}});
    auto args = parse_args(argv, spec, "view", &error);
    if (!args) return std::fprintf(stderr, "%s\n", error.c_str()), kExitUsage;
    const bool generated = args->has("--particles");
    if (args->positional.size() != (generated ? 0u : 1u)) {
        std::fprintf(stderr, "aquaform view: give exactly one scene file, e.g. aquaform view assets/scenes/dam_break.json, "
                             "or --particles N alone for a generated dam break\n");
        return kExitUsage;
    }
    Scene scene;
    if (generated) {
        // The benchmarks' dam break (study/bench_scenes.h), for frame rates at a chosen size.
        auto n = parse_positive("--particles", args->value("--particles"), &error);
        if (!n) return std::fprintf(stderr, "aquaform view: %s\n", error.c_str()), kExitUsage;
        scene = study::bench_scene(uint32_t(std::min<long>(*n, 1L << 26)), 4);
    } else {
        auto loaded = load_scene(args->positional[0]);
        if (!loaded) return std::fprintf(stderr, "aquaform: %s\n", loaded.error().c_str()), kExitUsage;
        scene = loaded.value();
    }
    auto plan = session::plan_session(scene);
    if (!plan) return std::fprintf(stderr, "aquaform: %s\n", plan.error().c_str()), kExitUsage;
    auto method_settings = render_method_from(*args, &error);
    if (!method_settings) return std::fprintf(stderr, "aquaform view: %s\n", error.c_str()), kExitUsage;
    const std::string method = method_settings->method();
    if (std::find(view_methods().begin(), view_methods().end(), method) == view_methods().end()) {
        std::string menu;
        for (const auto& m : view_methods()) menu += (menu.empty() ? "" : ", ") + m;
        return std::fprintf(stderr, "aquaform view: --method %s is too slow to watch; use one of %s\n", method.c_str(),
                            menu.c_str()),
               kExitUsage;
    }
    // The panel edits the SPH surface methods' settings; the other methods start at their defaults.
    const SurfaceSettings* given = method_settings->get<SurfaceSettings>();
    const std::optional<SurfaceSettings> settings = given ? *given : SurfaceSettings{};
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
    float picture_scale = 1.0f;
    if (args->has("--scale")) {
        char* end = nullptr;
        const std::string text = args->value("--scale");
        picture_scale = std::strtof(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0' || !(picture_scale >= 0.1f && picture_scale <= 1.0f))
            return std::fprintf(stderr, "aquaform view: --scale is the picture's size against the window's, 0.1 to 1; got \"%s\"\n",
                                text.c_str()),
                   kExitUsage;
    }
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
    // The swapchain goes before the device, also when an error (a scene too large for the
    // device, say) unwinds this function.
    struct DetachFirst {
        ViewWindow& window;
        ~DetachFirst() { window.detach(); }
    } detach_first{win};
    int status = kExitOk;
    {
        // Hot reload watches --shaders DIR, else the source tree's shaders/ beside the build.
        std::error_code ec;
        fs::path shaders = args->has("--shaders") ? fs::path(args->value("--shaders"))
                                                  : fs::read_symlink("/proc/self/exe", ec).parent_path() / ".." / "shaders";
        if (fs::is_directory(shaders)) {
            shaders = fs::weakly_canonical(shaders, ec);
        } else {
            if (args->has("--shaders"))
                std::fprintf(stderr, "aquaform view: --shaders %s is not a directory; shader hot reload is off\n",
                             shaders.string().c_str());
            shaders.clear();
        }
        // --async keeps a script's window free of the worker (a stress test of the threads).
        const bool lockstep = (args->has("--script") || !record_dir.empty()) && !args->has("--async");
        Viewer viewer(ctx, win, std::move(plan.value()), *settings, method, shaders, lockstep);
        viewer.set_screenshot_dir(record_dir.empty() ? fs::path(".") : record_dir);
        viewer.set_picture_scale(picture_scale);
        status = viewer.run(script, record_dir, max_frames);
    }
    return exit_status(ctx, status);
}

}  // namespace aquaform::cli
