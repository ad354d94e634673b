// Shared by every pass: the per-frame camera, prepended to each pass's WGSL at load time.
// Mirrored by `taut_render::frame::FrameUniform` (field names and order match).

struct Frame {
    view_from_world: mat4x4<f32>,
    clip_from_view: mat4x4<f32>,
    // Camera position in world space (w unused).
    camera_position: vec4<f32>,
    // Viewport size in physical pixels (x, y), and 1 / size (z, w).
    viewport: vec4<f32>,
    // The clipping plane: what lies where dot(xyz, p) > w is cut away (xyz = 0: nothing is).
    clip_plane: vec4<f32>,
};

@group(0) @binding(0) var<uniform> frame: Frame;

fn clip_from_world(p: vec3<f32>) -> vec4<f32> {
    return frame.clip_from_view * frame.view_from_world * vec4<f32>(p, 1.0);
}

// Converts a clip-space position to pixels (origin top left).
fn pixel_from_clip(c: vec4<f32>) -> vec2<f32> {
    let ndc = c.xy / c.w;
    return vec2<f32>((ndc.x * 0.5 + 0.5) * frame.viewport.x, (0.5 - ndc.y * 0.5) * frame.viewport.y);
}

// Converts pixels (origin top left) at a clip-space depth and w back to clip space.
fn clip_from_pixel(px: vec2<f32>, z: f32, w: f32) -> vec4<f32> {
    let ndc = vec2<f32>(px.x * frame.viewport.z * 2.0 - 1.0, 1.0 - px.y * frame.viewport.w * 2.0);
    return vec4<f32>(ndc * w, z, w);
}

// How far `p` lies on the clipping plane's cut side (positive: cut away).
fn clip_distance(p: vec3<f32>) -> f32 {
    return dot(frame.clip_plane.xyz, p) - frame.clip_plane.w;
}
