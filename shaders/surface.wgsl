// The surface pass: smooth shaded, zebra (reflection lines), curvature colour, draft angle or
// highlight lines, with per-pixel normals interpolated from smooth vertex normals. Mirrored by
// `taut_render::passes::surface::SurfaceStyle`; the draft and highlight formulas by
// `taut_render::analysis`, whose doc explains them.

struct SurfaceStyle {
    // 0 shaded, 1 zebra, 2 curvature colour, 3 ghost (shaded base colour with its alpha),
    // 4 draft angle, 5 highlight lines.
    mode: u32,
    // Black/white stripe pairs across a half turn of reflected directions.
    stripes: f32,
    // Direction of the light tubes on screen, radians (0: horizontal stripes).
    stripe_angle: f32,
    // Fraction of each period that is dark, in (0, 1).
    stripe_width: f32,
    // Values mapped to the two ends of the colour map.
    range_min: f32,
    range_max: f32,
    // Draft: the sine of the threshold angle.
    draft_sin: f32,
    // Highlight: the number of tubes.
    tube_count: f32,
    base_color: vec4<f32>,
    stripe_dark: vec4<f32>,
    stripe_light: vec4<f32>,
    // Draft: the unit pull direction in display coordinates; w = 1 pulls towards the camera.
    pull: vec4<f32>,
    // Highlight: the unit direction along the tubes (xyz) and their spacing (w).
    tube_direction: vec4<f32>,
    // Highlight: the unit normal H of the tubes' plane (xyz) and its height above the origin (w).
    tube_plane: vec4<f32>,
    // Draft: the colours of positive draft, of the band below the threshold, of undercuts.
    draft_positive: vec4<f32>,
    draft_below: vec4<f32>,
    draft_negative: vec4<f32>,
};

@group(1) @binding(0) var<uniform> style: SurfaceStyle;
@group(1) @binding(1) var colormap: texture_2d<f32>;
@group(1) @binding(2) var colormap_sampler: sampler;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) value: f32,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) view_position: vec3<f32>,
    @location(1) view_normal: vec3<f32>,
    @location(2) value: f32,
    // Display coordinates, for the views fixed to the model (draft, highlight lines).
    @location(3) world_position: vec3<f32>,
    @location(4) world_normal: vec3<f32>,
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    let view = frame.view_from_world * vec4<f32>(in.position, 1.0);
    out.clip = frame.clip_from_view * view;
    out.view_position = view.xyz;
    out.view_normal = (frame.view_from_world * vec4<f32>(in.normal, 0.0)).xyz;
    out.value = in.value;
    out.world_position = in.position;
    out.world_normal = in.normal;
    return out;
}

// Two-sided studio lighting in view space: a key light from the upper left, a fill from the
// right and a little ambient.
fn lighting(n: vec3<f32>, v: vec3<f32>) -> f32 {
    let key = normalize(vec3<f32>(-0.4, 0.6, 0.7));
    let fill = normalize(vec3<f32>(0.7, -0.2, 0.5));
    let h = normalize(key + v);
    let diffuse = 0.7 * max(dot(n, key), 0.0) + 0.25 * max(dot(n, fill), 0.0);
    let specular = 0.25 * pow(max(dot(n, h), 0.0), 48.0);
    return 0.18 + diffuse + specular;
}

@fragment
fn fs_main(in: VertexOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    if (clip_distance(in.world_position) > 0.0) {
        discard;
    }
    // Towards the eye; a parallel projection (w row (0, 0, 0, 1)) looks along view −z everywhere.
    var v = normalize(-in.view_position);
    if (frame.clip_from_view[3][3] > 0.5) {
        v = vec3<f32>(0.0, 0.0, 1.0);
    }
    var n = normalize(in.view_normal);
    if (!front) {
        n = -n;
    }
    if (style.mode == 1u) {
        // Reflection of parallel light tubes along the screen direction `axis`: the stripe
        // phase is the angle of the reflected ray around that axis, so stripes move with the
        // camera, break where the tangent plane breaks (G1) and kink where curvature does (G2).
        let r = reflect(-v, n);
        let axis = vec3<f32>(cos(style.stripe_angle), sin(style.stripe_angle), 0.0);
        let across = vec3<f32>(-axis.y, axis.x, 0.0);
        let phi = atan2(dot(r, across), dot(r, vec3<f32>(0.0, 0.0, 1.0)));
        let t = phi * style.stripes / 3.14159265;
        let f = fract(t);
        // Anti-aliased stripe edges from the screen-space rate of change of the phase.
        // The dark band is [0, stripe_width) of each period; coverage ramps over one pixel.
        let w = clamp(fwidth(t), 1e-4, 0.5);
        let trailing = clamp((style.stripe_width - f) / w + 0.5, 0.0, 1.0);
        let leading = clamp(f / w + 0.5, 0.0, 1.0);
        let next = clamp((f - 1.0) / w + 0.5, 0.0, 1.0);
        let dark = clamp(min(trailing, leading) + next, 0.0, 1.0);
        let color = mix(style.stripe_light, style.stripe_dark, dark);
        return vec4<f32>(color.rgb, 1.0);
    }
    let shade = lighting(n, v);
    if (style.mode == 4u) {
        return vec4<f32>(draft_color(normalize(in.world_normal)) * (0.55 + 0.45 * min(shade, 1.2)), 1.0);
    }
    if (style.mode == 5u) {
        let dark = highlight_coverage(in.world_position, normalize(in.world_normal));
        let clay = style.base_color.rgb * min(0.35 + 0.75 * shade, 1.25);
        return vec4<f32>(mix(clay, style.stripe_dark.rgb, dark), 1.0);
    }
    if (style.mode == 2u) {
        let span = max(style.range_max - style.range_min, 1e-30);
        let u = clamp((in.value - style.range_min) / span, 0.0, 1.0);
        // Sample the middle of the texel row; keep u inside the first and last texel centres.
        let coord = vec2<f32>(0.5 / 256.0 + u * (255.0 / 256.0), 0.5);
        let c = textureSampleLevel(colormap, colormap_sampler, coord, 0.0).rgb;
        return vec4<f32>(c * (0.55 + 0.45 * min(shade, 1.2)), 1.0);
    }
    if (style.mode == 3u) {
        return vec4<f32>(style.base_color.rgb * min(shade, 1.2), style.base_color.a);
    }
    return vec4<f32>(style.base_color.rgb * shade, 1.0);
}

// Draft: the sine of the angle between the surface and the pull, n·p for the surface's own
// (unflipped) normal, coloured by class; the class edges blend over one pixel.
fn draft_color(n: vec3<f32>) -> vec3<f32> {
    var pull = style.pull.xyz;
    if (style.pull.w > 0.5) {
        // The camera's backward axis (view space +z) in display coordinates.
        let m = frame.view_from_world;
        pull = normalize(vec3<f32>(m[0].z, m[1].z, m[2].z));
    }
    let s = dot(n, pull);
    let w = max(fwidth(s), 1e-6);
    let positive = clamp((s - style.draft_sin) / w + 0.5, 0.0, 1.0);
    let negative = clamp((-style.draft_sin - s) / w + 0.5, 0.0, 1.0);
    let c = mix(mix(style.draft_below.rgb, style.draft_positive.rgb, positive), style.draft_negative.rgb, negative);
    return c;
}

// Highlight lines: how much of this pixel a line covers. The normal line p + μn meets the
// tubes' plane at q; u is q's coordinate across the tubes in spacings, 0 at the first tube.
fn highlight_coverage(p: vec3<f32>, n: vec3<f32>) -> f32 {
    let e = style.tube_direction.xyz;
    let h = style.tube_plane.xyz;
    let d = cross(e, h);
    var nh = dot(n, h);
    if (abs(nh) < 1e-6) {
        nh = select(-1e-6, 1e-6, nh >= 0.0);
    }
    let q = p + ((style.tube_plane.w - dot(p, h)) / nh) * n;
    let u = dot(q, d) / style.tube_direction.w + 0.5 * (style.tube_count - 1.0);
    // Pixels per unit of u: lines about two pixels wide, anti-aliased.
    let w = max(fwidth(u), 1e-6);
    let k = round(u);
    var cover = clamp(1.5 - abs(u - k) / w, 0.0, 1.0);
    if (k < -0.5 || k > style.tube_count - 0.5) {
        cover = 0.0;
    }
    // Where lines crowd closer than a few pixels, grey instead of noise.
    return mix(cover, 0.35, clamp((w - 0.2) / 0.3, 0.0, 1.0));
}
