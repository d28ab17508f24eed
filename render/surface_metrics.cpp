#include "render/surface_metrics.h"

#include "core/error.h"
#include "pictures/image_metrics.h"
#include "shaders/shared/render/anisotropy.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include <glm/glm.hpp>

namespace aquaform {

namespace {

void require_well_formed(const SurfaceFrame& frame, const std::string& what) {
    const size_t pixels = size_t(frame.width) * frame.height;
    if (frame.hit.size() != pixels || frame.normal.size() != pixels)
        throw Failure(what + " frame is malformed: " + size_text(frame.width, frame.height) + " pixels but " +
                      std::to_string(frame.hit.size()) + " hits and " + std::to_string(frame.normal.size()) +
                      " normals");
    if (frame.color.width != frame.width || frame.color.height != frame.height)
        throw Failure(what + " frame is " + size_text(frame.width, frame.height) + " pixels but its colour image is " +
                      size_text(frame.color.width, frame.color.height));
    require_well_formed(frame.color, what + " colour image");
}

void require_comparable(const SurfaceFrame& reference, const SurfaceFrame& test, float particle_radius) {
    require_well_formed(reference, "the reference");
    require_well_formed(test, "the test");
    if (reference.width != test.width || reference.height != test.height)
        throw Failure("cannot compare surfaces of different sizes: the reference is " +
                      size_text(reference.width, reference.height) + " pixels, the test " +
                      size_text(test.width, test.height));
    if (!(particle_radius > 0.0f) || !std::isfinite(particle_radius))
        throw Failure("cannot compare surfaces: the particle radius must be positive, not " +
                      std::to_string(particle_radius));
}

double mean(const std::vector<double>& values) {
    return values.empty() ? 0.0 : std::accumulate(values.begin(), values.end(), 0.0) / double(values.size());
}

/// Nearest-rank percentile (0 for no values); reorders `values`.
double percentile(std::vector<double>& values, double fraction) {
    if (values.empty()) return 0.0;
    const size_t rank = size_t(std::ceil(fraction * double(values.size())));
    const auto nth = values.begin() + std::ptrdiff_t(std::clamp<size_t>(rank, 1, values.size()) - 1);
    std::nth_element(values.begin(), nth, values.end());
    return *nth;
}

/// Angle between two vectors of any length, accurate for small angles too (unlike acos of the dot).
double angle_degrees(const glm::vec3& a, const glm::vec3& b) {
    const glm::dvec3 da(a), db(b);
    return glm::degrees(std::atan2(glm::length(glm::cross(da, db)), glm::dot(da, db)));
}

}  // namespace

SurfaceErrorMaps surface_error_maps(const SurfaceFrame& reference, const SurfaceFrame& test, float particle_radius) {
    require_comparable(reference, test, particle_radius);
    const size_t pixels = size_t(reference.width) * reference.height;
    SurfaceErrorMaps maps{std::vector<float>(pixels, 0.0f), std::vector<float>(pixels, 0.0f)};
    for (size_t i = 0; i < pixels; ++i) {
        if (!reference.has_surface(i) || !test.has_surface(i)) continue;
        maps.depth_err[i] = std::abs(test.hit[i].w - reference.hit[i].w) / particle_radius;
        maps.normal_err_deg[i] = float(angle_degrees(glm::vec3(reference.normal[i]), glm::vec3(test.normal[i])));
    }
    return maps;
}

SurfaceComparison compare_surfaces(const SurfaceFrame& reference, const SurfaceFrame& test, float particle_radius) {
    const SurfaceErrorMaps maps = surface_error_maps(reference, test, particle_radius);
    SurfaceComparison result;
    std::vector<double> depth_errors, normal_errors;
    double evaluations = 0.0;
    for (size_t i = 0; i < maps.depth_err.size(); ++i) {
        const bool in_reference = reference.has_surface(i), in_test = test.has_surface(i);
        if (in_reference && in_test) {
            ++result.both_hit;
            depth_errors.push_back(maps.depth_err[i]);
            normal_errors.push_back(maps.normal_err_deg[i]);
        } else if (in_reference) {
            ++result.only_reference;
        } else if (in_test) {
            ++result.only_test;
        }
        if (test.normal[i].w > 0.0f) {
            ++result.rays;
            evaluations += test.normal[i].w;
        }
    }
    result.depth_err_mean = mean(depth_errors);
    result.depth_err_max = depth_errors.empty() ? 0.0 : *std::max_element(depth_errors.begin(), depth_errors.end());
    result.depth_err_p95 = percentile(depth_errors, 0.95);
    result.normal_err_deg_mean = mean(normal_errors);
    result.normal_err_deg_p95 = percentile(normal_errors, 0.95);
    const size_t with_surface = result.both_hit + result.only_reference + result.only_test;
    result.coverage_mismatch =
        double(result.only_reference + result.only_test) / double(std::max<size_t>(1, with_surface));
    result.psnr_db = psnr(reference.color, test.color);
    const SurfaceRoughness roughness = surface_roughness(reference, test, particle_radius);
    result.roughness_deg = roughness.rms_deg;
    result.flat_pixels = roughness.flat_pixels;
    result.evals_per_ray = result.rays == 0 ? 0.0 : evaluations / double(result.rays);
    return result;
}

SurfaceRoughness surface_roughness(const SurfaceFrame& reference, const SurfaceFrame& test, float particle_radius) {
    if (reference.width != test.width || reference.height != test.height || reference.hit.size() != test.hit.size())
        throw Failure("surface roughness: the frames differ in size");
    const int w = int(reference.width), h = int(reference.height);
    auto at = [&](int x, int y) { return size_t(y) * size_t(w) + size_t(x); };
    double sum_sq = 0.0;
    size_t flat = 0;
    for (int y = 1; y + 1 < h; y += int(kRoughnessStride))
        for (int x = 1; x + 1 < w; x += int(kRoughnessStride)) {
            const size_t p = at(x, y);
            if (!reference.has_surface(p) || !test.has_surface(p)) continue;
            // The window's half width in pixels: half the window's width over this pixel's
            // footprint, the least distance to a neighbour's surface point (a step in the
            // surface lengthens the others).
            float footprint = INFINITY;
            for (const size_t q : {at(x - 1, y), at(x + 1, y), at(x, y - 1), at(x, y + 1)})
                if (reference.has_surface(q))
                    footprint =
                        std::min(footprint, glm::length(glm::vec3(reference.hit[q]) - glm::vec3(reference.hit[p])));
            if (!(footprint > 0.0f && footprint < INFINITY)) continue;
            const int half = int(std::lround(0.5f * kRoughnessWindowRadii * particle_radius / footprint));
            if (half < 2 || half > 16 || x - half < 0 || y - half < 0 || x + half >= w || y + half >= h) continue;
            // The plane through the window's surface points (their covariance's least axis).
            const float t0 = reference.hit[p].w;
            glm::dvec3 mean(0.0);
            std::vector<glm::vec3> points;
            bool continuous = true;
            for (int dy = -half; dy <= half && continuous; ++dy)
                for (int dx = -half; dx <= half; ++dx) {
                    const glm::vec4& q = reference.hit[at(x + dx, y + dy)];
                    if (q.w < 0.0f || std::abs(q.w - t0) > kRoughnessWindowRadii * particle_radius) {
                        continuous = false;
                        break;
                    }
                    points.emplace_back(q);
                    mean += glm::dvec3(q);
                }
            if (!continuous) continue;
            mean /= double(points.size());
            glm::mat3 covariance(0.0f);
            for (const glm::vec3& q : points) {
                const glm::vec3 d = (q - glm::vec3(mean)) / particle_radius;  // of order 1 (symmetric_eigen)
                covariance += glm::outerProduct(d, d);
            }
            covariance /= float(points.size());
            const shader::SymmetricEigen e = shader::symmetric_eigen(covariance);
            if (!(std::sqrt(std::max(e.values[2], 0.0f)) <= kFlatResidualRadii)) continue;  // not flat
            glm::vec3 plane = glm::normalize(e.vectors[2]);
            if (glm::dot(plane, glm::vec3(reference.normal[p])) < 0.0f) plane = -plane;
            const glm::vec3 n(test.normal[p]);
            const float len = glm::length(n);
            if (!(len > 0.0f)) continue;
            const double angle = glm::degrees(std::acos(std::clamp(double(glm::dot(plane, n / len)), -1.0, 1.0)));
            sum_sq += angle * angle;
            ++flat;
        }
    return {flat ? std::sqrt(sum_sq / double(flat)) : 0.0, flat};
}

}  // namespace aquaform
