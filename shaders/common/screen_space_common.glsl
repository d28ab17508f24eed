// Helpers of the screen-space filters (layout in shared/render/screen_space_layout.h). Include after
// declaring `ss` (ScreenSpaceParams).

uint ss_index(ivec2 pixel) { return uint(pixel.y) * ss.screen.x + uint(pixel.x); }

bool ss_inside(ivec2 pixel) {
    return all(greaterThanEqual(pixel, ivec2(0))) && all(lessThan(pixel, ivec2(ss.screen.xy)));
}

/// Kernel of the bilateral and narrow-range filters at a pixel of eye depth `depth`: the world
/// sigma projected to pixels, cut at 3 sigma and capped at the largest half-width; a capped
/// kernel shrinks its sigma with it so that it keeps its Gaussian shape (as Truong's own code does).
void ss_kernel(float depth, out int radius, out float sigma_px) {
    float projected = ss.sigma * ss.pixel_scale / depth;
    float cap = float(ss.screen.w);
    radius = int(min(ceil(3.0 * projected), cap));
    sigma_px = min(projected, cap / 3.0);
}
