// The surface pass: smooth shaded, zebra (reflection lines) or curvature colour, with
// per-pixel normals interpolated from smooth vertex normals. Mirrored by
// `taut_render::passes::surface::SurfaceStyle`.

struct SurfaceStyle {
    // 0 shaded, 1 zebra, 2 curvature colour, 3 ghost (shaded base colour with its alpha).
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
    _pad0: f32,
    _pad1: f32,
    base_color: vec4<f32>,
    stripe_dark: vec4<f32>,
    stripe_light: vec4<f32>,
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
};

@vertex
fn vs_main(in: VertexIn) -> VertexOut {
    var out: VertexOut;
    let view = frame.view_from_world * vec4<f32>(in.position, 1.0);
    out.clip = frame.clip_from_view * view;
    out.view_position = view.xyz;
    out.view_normal = (frame.view_from_world * vec4<f32>(in.normal, 0.0)).xyz;
    out.value = in.value;
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
    let v = normalize(-in.view_position);
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
