// The reference-image pass: one textured quad per picture, on its plane or facing the camera,
// alpha blended at the image's opacity. No depth is written or tested: drawn before the surface
// an image is behind the whole model, drawn after it over it.
// Mirrored by `taut_render::passes::reference_images::ReferenceImageUniform`.

struct ReferenceImage {
    // xyz: the centre in display coordinates; w: opacity.
    centre: vec4<f32>,
    // xyz: half the width along the picture's right, half the height along its up (planar
    // pictures); w: 1 when the picture faces the camera instead.
    right: vec4<f32>,
    up: vec4<f32>,
    // Facing the camera: half width, half height, cos and sin of the rotation.
    billboard: vec4<f32>,
};

@group(1) @binding(0) var<uniform> image: ReferenceImage;
@group(2) @binding(0) var picture: texture_2d<f32>;
@group(2) @binding(1) var picture_sampler: sampler;

struct PictureOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_main(@builtin(vertex_index) vertex: u32) -> PictureOut {
    var corners = array<vec2<f32>, 6>(
        vec2<f32>(-1.0, -1.0), vec2<f32>(1.0, -1.0), vec2<f32>(-1.0, 1.0),
        vec2<f32>(-1.0, 1.0), vec2<f32>(1.0, -1.0), vec2<f32>(1.0, 1.0),
    );
    let corner = corners[vertex % 6u];
    var right = image.right.xyz;
    var up = image.up.xyz;
    if (image.right.w > 0.5) {
        // The camera's right and up in world space: the first two rows of its rotation.
        let v = frame.view_from_world;
        let screen_right = vec3<f32>(v[0].x, v[1].x, v[2].x);
        let screen_up = vec3<f32>(v[0].y, v[1].y, v[2].y);
        let c = image.billboard.z;
        let s = image.billboard.w;
        right = (screen_right * c + screen_up * s) * image.billboard.x;
        up = (screen_up * c - screen_right * s) * image.billboard.y;
    }
    var out: PictureOut;
    out.clip = clip_from_world(image.centre.xyz + right * corner.x + up * corner.y);
    // Row 0 of the picture is its top.
    out.uv = vec2<f32>(0.5 + 0.5 * corner.x, 0.5 - 0.5 * corner.y);
    return out;
}

@fragment
fn fs_main(in: PictureOut) -> @location(0) vec4<f32> {
    let texel = textureSample(picture, picture_sampler, in.uv);
    return vec4<f32>(texel.rgb, texel.a * image.centre.w);
}
