// The wireframe overlay: a cube seen face-on draws its outline where the pinhole camera puts it,
// leaves the face's inside alone, and edges behind the eye draw nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/primitives.h"
#include "render/wireframe.h"

namespace aquaform {
namespace {

Image blank(uint32_t w, uint32_t h) {
    Image image;
    image.width = w;
    image.height = h;
    image.rgba.assign(size_t(w) * h * 4, 0);
    return image;
}

bool drawn(const Image& image, int x, int y) {
    const uint8_t* px = &image.rgba[(size_t(y) * image.width + size_t(x)) * 4];
    return px[0] > 100;
}

ViewCamera facing_cube() {
    ViewCamera camera;
    camera.eye = {0.0f, 0.0f, 3.0f};
    camera.target = {0.0f, 0.0f, 0.0f};
    camera.fov_y_degrees = 40.0f;
    return camera;
}

TEST(WireframeTest, CubeOutlineLandsWhereTheCameraProjectsIt) {
    const geometry::Mesh cube = geometry::make_box({{-0.5f, -0.5f, -0.5f}, {0.5f, 0.5f, 0.5f}});
    Image image = blank(128, 128);
    draw_wireframe(image, cube.vertices, cube.faces, facing_cube());
    // The front face (z = 0.5, 2.5 from the eye) spans 0.5 / (2.5 tan 20 deg) of the half width.
    const float half = 0.5f / (2.5f * std::tan(glm::radians(20.0f))) * 64.0f;
    const int left = int(std::lround(63.5f - half)), right = int(std::lround(63.5f + half));
    bool left_edge = false, right_edge = false;
    for (int dx = -1; dx <= 1; ++dx) {
        left_edge = left_edge || drawn(image, left + dx, 64);
        right_edge = right_edge || drawn(image, right + dx, 64);
    }
    EXPECT_TRUE(left_edge && right_edge) << "the front face's vertical edges, near x = " << left << " and " << right;
    EXPECT_FALSE(drawn(image, 64 + int(half * 0.5f), 64 + int(half * 0.5f)))
        << "inside the front face, away from its diagonal and from the back face's outline";
    EXPECT_FALSE(drawn(image, 2, 2)) << "outside the cube";
}

TEST(WireframeTest, EdgesBehindTheEyeDrawNothingAndBadIndicesAreSkipped) {
    Image image = blank(64, 64);
    const std::vector<glm::vec3> vertices{{0.0f, 0.0f, 4.0f}, {1.0f, 0.0f, 5.0f}, {0.0f, 1.0f, 4.5f}};
    draw_wireframe(image, vertices, {{0u, 1u, 2u}, {0u, 1u, 99u}}, facing_cube());
    for (uint8_t v : image.rgba) ASSERT_EQ(v, 0u);
}

}  // namespace
}  // namespace aquaform
