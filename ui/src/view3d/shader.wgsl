// cloth-ui's 3D view: lit, two-sided triangles (the cloth textured with its painted
// texture, the body in a flat colour) and unlit lines (cut edges, the pinch spring, the
// floor grid). Lighting is done in linear colour; the target is a gamma-space Rgba8Unorm
// texture like egui's own, so the output is encoded to sRGB here.

struct Uniforms {
    view_proj: mat4x4<f32>,
    light_dir: vec4<f32>,
    eye: vec4<f32>,
};

@group(0) @binding(0) var<uniform> u: Uniforms;
@group(0) @binding(1) var cloth_tex: texture_2d<f32>;
@group(0) @binding(2) var cloth_samp: sampler;

struct VIn {
    @location(0) pos: vec3<f32>,
    @location(1) nrm: vec3<f32>,
    @location(2) uv: vec2<f32>,
    @location(3) col: vec4<f32>,
};

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) nrm: vec3<f32>,
    @location(1) uv: vec2<f32>,
    @location(2) col: vec4<f32>,
    @location(3) world: vec3<f32>,
};

fn transform(v: VIn) -> VOut {
    var o: VOut;
    o.clip = u.view_proj * vec4<f32>(v.pos, 1.0);
    o.nrm = v.nrm;
    o.uv = v.uv;
    o.col = v.col;
    o.world = v.pos;
    return o;
}

@vertex
fn vs(v: VIn) -> VOut {
    return transform(v);
}

// Lines that trace a surface (the cloth's border) sit a little in front of it, so the
// depth test does not hide them: the vertex moves towards the eye by `nrm.x` metres (a
// world distance, unlike a depth bias, so a line shows through nothing farther off).
@vertex
fn vs_line(v: VIn) -> VOut {
    var w = v;
    w.pos = v.pos + normalize(u.eye.xyz - v.pos) * v.nrm.x;
    return transform(w);
}

fn to_srgb(c: vec3<f32>) -> vec3<f32> {
    return pow(clamp(c, vec3<f32>(0.0), vec3<f32>(1.0)), vec3<f32>(1.0 / 2.2));
}

fn shade(base: vec3<f32>, nrm: vec3<f32>, world: vec3<f32>, front: bool) -> vec3<f32> {
    var n = normalize(nrm);
    // Two-sided: light the side facing the viewer.
    let to_eye = normalize(u.eye.xyz - world);
    if (dot(n, to_eye) < 0.0) {
        n = -n;
    }
    let l = normalize(u.light_dir.xyz);
    let diffuse = max(dot(n, l), 0.0);
    let fill = 0.5 * max(dot(n, normalize(vec3<f32>(-0.4, 0.3, -0.6))), 0.0);
    let h = normalize(l + to_eye);
    let spec = 0.08 * pow(max(dot(n, h), 0.0), 24.0);
    var k = 0.22 + 0.75 * diffuse + 0.25 * fill;
    if (!front) {
        // The back of the cloth a little darker, so a fold reads.
        k = k * 0.8;
    }
    return base * k + vec3<f32>(spec);
}

@fragment
fn fs_textured(i: VOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    let t = textureSample(cloth_tex, cloth_samp, i.uv).rgb;
    return vec4<f32>(to_srgb(shade(t * i.col.rgb, i.nrm, i.world, front)), 1.0);
}

@fragment
fn fs_colour(i: VOut, @builtin(front_facing) front: bool) -> @location(0) vec4<f32> {
    return vec4<f32>(to_srgb(shade(i.col.rgb, i.nrm, i.world, front)), 1.0);
}

@fragment
fn fs_flat(i: VOut) -> @location(0) vec4<f32> {
    return vec4<f32>(to_srgb(i.col.rgb), 1.0);
}
