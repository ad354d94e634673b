// The lines pass: each instance is one segment drawn as a screen-space quad (6 vertices, two
// triangles) `width_px` pixels wide, with round ends and anti-aliased edges (coverage from the
// pixel's distance to the segment). Mirrored by `taut_render::passes::lines::LineInstance`.

struct LineInstance {
    @location(0) a: vec3<f32>,
    @location(1) width_px: f32,
    @location(2) b: vec3<f32>,
    @location(3) color: vec4<f32>,
};

struct LineOut {
    @builtin(position) clip: vec4<f32>,
    // Pixels from the first end, along the segment (x) and across it (y): screen-linear.
    @location(0) @interpolate(linear) local: vec2<f32>,
    @location(1) @interpolate(flat) length_px: f32,
    @location(2) @interpolate(flat) half_width: f32,
    @location(3) @interpolate(flat) color: vec4<f32>,
};

// Fraction of its distance to the eye by which a depth-tested line is moved towards the eye, so
// a line lying on the surface wins the depth test (the surface pass also biases itself back).
// Scaling about the eye leaves the line's pixels where they were (in perspective).
const SURFACE_LINE_PULL: f32 = 2e-3;

// Outside every clip volume: a quad whose six corners are all here has no area.
const DROPPED: vec4<f32> = vec4<f32>(2.0, 2.0, 2.0, 1.0);

fn clip_pulled(p: vec3<f32>, pull: f32) -> vec4<f32> {
    let view = frame.view_from_world * vec4<f32>(p, 1.0);
    // A parallel projection (w row (0, 0, 0, 1)) pulls along view z only, so the pixel stays;
    // by as much as perspective pulls at the target (its eye stands farther back, see
    // `Camera::eye`): the target's distance is about 3 half-heights at the default field of view.
    if (frame.clip_from_view[3][3] > 0.5) {
        let half_height = 1.0 / frame.clip_from_view[1][1];
        return frame.clip_from_view * vec4<f32>(view.xy, view.z + pull * 3.0 * half_height, 1.0);
    }
    return frame.clip_from_view * vec4<f32>(view.xyz * (1.0 - pull), 1.0);
}

fn line_vertex(vertex: u32, line: LineInstance, pull: f32, on_top: bool) -> LineOut {
    var out: LineOut;
    var a = line.a;
    var b = line.b;
    // Lines on the surface are cut by the clipping plane as the surface is; on-top ones (the
    // cage, gizmos, measurements) are not.
    if (!on_top) {
        let da = clip_distance(a);
        let db = clip_distance(b);
        if (da > 0.0 && db > 0.0) {
            out.clip = DROPPED;
            return out;
        }
        if (da > 0.0) {
            a = mix(a, b, da / (da - db));
        } else if (db > 0.0) {
            b = mix(b, a, db / (db - da));
        }
    }
    var ca = clip_pulled(a, pull);
    var cb = clip_pulled(b, pull);
    // Keep the part in front of the near plane (z = 0 in wgpu's clip space, where w > 0): a
    // segment reaching behind the camera is cut there, one wholly behind draws nothing.
    if (ca.z < 0.0 && cb.z < 0.0) {
        out.clip = DROPPED;
        return out;
    }
    if (ca.z < 0.0) {
        ca = mix(ca, cb, ca.z / (ca.z - cb.z));
    } else if (cb.z < 0.0) {
        cb = mix(cb, ca, cb.z / (cb.z - ca.z));
    }
    let pa = pixel_from_clip(ca);
    let pb = pixel_from_clip(cb);
    let length_px = length(pb - pa);
    var dir = vec2<f32>(1.0, 0.0);
    if (length_px > 1e-4) {
        dir = (pb - pa) / length_px;
    }
    let across = vec2<f32>(-dir.y, dir.x);
    // Lines thinner than a pixel are drawn a pixel wide and fainter.
    let half_width = max(line.width_px, 1.0) * 0.5;
    // One pixel of margin beyond the round end and the edge for the anti-aliased fringe.
    let reach = half_width + 1.0;
    // (end, side) of the two triangles: end 0 is `a`, 1 is `b`.
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(0.0, 1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
    );
    let corner = corners[vertex % 6u];
    let at_b = corner.x > 0.5;
    let along = select(-reach, length_px + reach, at_b);
    let c = select(ca, cb, at_b);
    // On-top lines are tested against nothing: keep their depth inside the clip volume.
    let z = select(c.z, 0.0, on_top);
    out.clip = clip_from_pixel(pa + dir * along + across * (corner.y * reach), z, c.w);
    out.local = vec2<f32>(along, corner.y * reach);
    out.length_px = length_px;
    out.half_width = half_width;
    out.color = vec4<f32>(line.color.rgb, line.color.a * clamp(line.width_px, 0.0, 1.0));
    return out;
}

@vertex
fn vs_surface(@builtin(vertex_index) vertex: u32, line: LineInstance) -> LineOut {
    return line_vertex(vertex, line, SURFACE_LINE_PULL, false);
}

@vertex
fn vs_on_top(@builtin(vertex_index) vertex: u32, line: LineInstance) -> LineOut {
    return line_vertex(vertex, line, 0.0, true);
}

@fragment
fn fs_main(in: LineOut) -> @location(0) vec4<f32> {
    // Distance to the segment [0, length] × {0}: round ends come for free.
    let nearest = clamp(in.local.x, 0.0, in.length_px);
    let d = length(vec2<f32>(in.local.x - nearest, in.local.y));
    let coverage = clamp(in.half_width + 0.5 - d, 0.0, 1.0);
    if (coverage <= 0.0) {
        discard;
    }
    return vec4<f32>(in.color.rgb, in.color.a * coverage);
}
