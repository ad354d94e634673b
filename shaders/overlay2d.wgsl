// The 2D overlay pass: rectangles given in pixels (origin top left), drawn last, for the
// curvature legend: solid panels and ticks, the colour-map bar, and text from an 8 × 8 glyph
// atlas. Mirrored by `taut_render::passes::overlay2d::Rect2d`.

struct Rect2d {
    @location(0) min_px: vec2<f32>,
    @location(1) max_px: vec2<f32>,
    // Interpolated from `uv_min` at the top-left corner to `uv_max` at the bottom-right one.
    @location(2) uv_min: vec2<f32>,
    @location(3) uv_max: vec2<f32>,
    @location(4) color: vec4<f32>,
    // 0 solid `color`; 1 the colour map at t = uv.y (alpha from `color`); 2 a glyph: the atlas
    // texel at uv (texels) times `color`.
    @location(5) kind: u32,
};

struct RectOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
    @location(1) @interpolate(flat) color: vec4<f32>,
    @location(2) @interpolate(flat) kind: u32,
};

// The same 256 × 1 table the surface pass samples, so bar and surface cannot disagree.
@group(1) @binding(0) var colormap: texture_2d<f32>;
@group(1) @binding(1) var colormap_sampler: sampler;
// Coverage of the glyphs, one byte a texel, read texel by texel (nearest).
@group(1) @binding(2) var glyphs: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32, rect: Rect2d) -> RectOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(0.0, 0.0), vec2<f32>(1.0, 0.0), vec2<f32>(0.0, 1.0),
        vec2<f32>(0.0, 1.0), vec2<f32>(1.0, 0.0), vec2<f32>(1.0, 1.0),
    );
    let f = corners[vertex % 6u];
    var out: RectOut;
    out.clip = clip_from_pixel(mix(rect.min_px, rect.max_px, f), 0.0, 1.0);
    out.uv = mix(rect.uv_min, rect.uv_max, f);
    out.color = rect.color;
    out.kind = rect.kind;
    return out;
}

@fragment
fn fs_main(in: RectOut) -> @location(0) vec4<f32> {
    if (in.kind == 1u) {
        // Texel centres of the first and last entries at t = 0 and 1, as in surface.wgsl.
        let u = 0.5 / 256.0 + clamp(in.uv.y, 0.0, 1.0) * (255.0 / 256.0);
        let c = textureSampleLevel(colormap, colormap_sampler, vec2<f32>(u, 0.5), 0.0).rgb;
        return vec4<f32>(c, in.color.a);
    }
    if (in.kind == 2u) {
        let size = vec2<i32>(textureDimensions(glyphs));
        let texel = clamp(vec2<i32>(floor(in.uv)), vec2<i32>(0), size - 1);
        let coverage = textureLoad(glyphs, texel, 0).r;
        if (coverage <= 0.0) {
            discard;
        }
        return vec4<f32>(in.color.rgb, in.color.a * coverage);
    }
    return in.color;
}
