// The points pass: each instance is a disc or a ring around a point, `radius_px` pixels in
// radius, drawn as a screen-space quad (6 vertices) on top of everything, anti-aliased.
// Mirrored by `taut_render::passes::points::PointInstance`.

struct PointInstance {
    @location(0) position: vec3<f32>,
    @location(1) radius_px: f32,
    @location(2) color: vec4<f32>,
    // Thickness of a ring in pixels; 0 for a filled disc.
    @location(3) ring_px: f32,
};

struct PointOut {
    @builtin(position) clip: vec4<f32>,
    // Pixels from the centre: screen-linear.
    @location(0) @interpolate(linear) local: vec2<f32>,
    @location(1) @interpolate(flat) radius_px: f32,
    @location(2) @interpolate(flat) ring_px: f32,
    @location(3) @interpolate(flat) color: vec4<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32, point: PointInstance) -> PointOut {
    var out: PointOut;
    let c = clip_from_world(point.position);
    // Behind the near plane (or the eye): nothing to draw; a zero-area quad.
    if (c.z < 0.0 || c.w <= 0.0) {
        out.clip = vec4<f32>(2.0, 2.0, 2.0, 1.0);
        return out;
    }
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(-1.0, 1.0),
        vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
    );
    let radius = max(point.radius_px, 0.5);
    // One pixel of margin for the anti-aliased rim.
    let local = corners[vertex % 6u] * (radius + 1.0);
    out.clip = clip_from_pixel(pixel_from_clip(c) + local, 0.0, c.w);
    out.local = local;
    out.radius_px = radius;
    out.ring_px = point.ring_px;
    out.color = point.color;
    return out;
}

@fragment
fn fs_main(in: PointOut) -> @location(0) vec4<f32> {
    let d = length(in.local);
    var coverage = clamp(in.radius_px + 0.5 - d, 0.0, 1.0);
    if (in.ring_px > 0.0) {
        coverage = min(coverage, clamp(d - (in.radius_px - in.ring_px) + 0.5, 0.0, 1.0));
    }
    if (coverage <= 0.0) {
        discard;
    }
    return vec4<f32>(in.color.rgb, in.color.a * coverage);
}
