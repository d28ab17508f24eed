// Lets a header be included by both C++ (with GLM types) and GLSL, so that layouts and the
// math of the kernels exist once. In C++ everything lands in namespace aquaform::shader.
#ifndef AQUAFORM_SHADER_COMPAT_H
#define AQUAFORM_SHADER_COMPAT_H

#ifdef __cplusplus
#include <cstdint>
#include <glm/glm.hpp>
namespace aquaform::shader {
using glm::ivec3;
using glm::ivec4;
using glm::uvec3;
using glm::uvec4;
using glm::vec2;
using glm::vec3;
using glm::vec4;
using uint = uint32_t;
using glm::clamp;
using glm::cross;
using glm::dot;
using glm::floor;
using glm::inversesqrt;
using glm::length;
using glm::max;
using glm::min;
using glm::normalize;
using glm::pow;
using glm::sqrt;
using glm::mat3;
using glm::abs;
using glm::outerProduct;
using glm::transpose;
}  // namespace aquaform::shader
#define AF_BEGIN namespace aquaform::shader {
#define AF_END }
#define AF_FN inline
#else
#define AF_BEGIN
#define AF_END
#define AF_FN
#endif

#endif
