// Layout of the control-particle driving force (Karpati et al., section 3.1), shared by
// control/control_force.{h,cpp} and shaders/control/control_force.comp.
//
// The driving force is a pressure force whose pressure comes from the control particles, not
// from the fluid: each control point c with volume V_c and control pressure P (a suction, in Pa)
// adds to a fluid particle i the acceleration
//     a_i = (P / rho0) sum_c V_c grad_i W_poly6(x_i - x_c, H),
// which points into the region the control points fill (grad W points towards x_c). Written as
// a potential, a_i = (P / rho0) grad phi with phi = sum_c V_c W(x - x_c): about 1 inside a
// filled shape, 0 outside, so the shape is a well of depth P / rho0 per unit mass.
// A control point's set (mesh) is its w; each set carries its coefficient (P / rho0) V_c times
// a blend weight (for morphs) and a mask of the fluid tags it acts on.
// The kernel is poly6, not the spiky kernel of the fluid's pressure: the spiky gradient does not
// vanish at r = 0, so every control point would be a point attractor as strong as the shape's
// boundary, and the fluid inside a shape would never come to rest.
#ifndef AQUAFORM_CONTROL_LAYOUT_H
#define AQUAFORM_CONTROL_LAYOUT_H
#include "../core/compat.h"
#include "../core/sph_kernels.h"

#define CONTROL_MAX_SETS 8

AF_BEGIN

struct ControlSet {
    float coefficient;  ///< (P / rho0) V_c w  [m^5 / s^2]: acceleration = coefficient * grad W
    uint tag_mask;      ///< bit t set: acts on fluid particles with tag t (tags >= 31 share bit 31)
    float weight_volume;  ///< V_c w [m^3]: the set's share of phi
    uint pad0;
};

struct ControlParams {
    vec4 grid_origin_cell;  ///< the control points' own Morton grid: xyz origin, w cell size (= H)
    uvec4 grid_dims;        ///< xyz cells, w cell count
    float support;          ///< H [m]
    float support2;
    float gradient_coeff;   ///< poly6 normalisation for H (grad phi)
    uint set_count;
    float damping;          ///< rate [1/s] at which velocity decays where phi = 1 (see control_force.h)
    float pad0;
    float pad1;
    float pad2;
    ControlSet sets[CONTROL_MAX_SETS];
};

/// The bit of a fluid tag in ControlSet.tag_mask.
AF_FN uint control_tag_bit(float tag) { return 1u << min(uint(max(tag, 0.0f)), 31u); }

AF_END

#ifdef __cplusplus
static_assert(sizeof(aquaform::shader::ControlSet) == 16);
static_assert(sizeof(aquaform::shader::ControlParams) == 64 + 16 * CONTROL_MAX_SETS);
#endif

#endif
