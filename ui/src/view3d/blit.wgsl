// Shows the 3D view's colour texture in egui's render pass: one full-viewport triangle,
// one texture sample, no blending. egui's own image shader costs several times more per
// pixel on a software rasteriser (it keeps a software-filtering branch that llvmpipe
// runs for every pixel), and the view is most of the window.

@group(0) @binding(0) var view_tex: texture_2d<f32>;
@group(0) @binding(1) var view_samp: sampler;

struct VOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs(@builtin(vertex_index) i: u32) -> VOut {
    let uv = vec2<f32>(f32((i << 1u) & 2u), f32(i & 2u));
    var o: VOut;
    o.clip = vec4<f32>(uv.x * 2.0 - 1.0, 1.0 - uv.y * 2.0, 0.0, 1.0);
    o.uv = uv;
    return o;
}

// The view texture holds gamma-encoded colour (see shader.wgsl).
@fragment
fn fs_gamma(i: VOut) -> @location(0) vec4<f32> {
    return vec4<f32>(textureSample(view_tex, view_samp, i.uv).rgb, 1.0);
}

// For an sRGB framebuffer, which encodes on write.
@fragment
fn fs_linear(i: VOut) -> @location(0) vec4<f32> {
    let c = textureSample(view_tex, view_samp, i.uv).rgb;
    return vec4<f32>(pow(c, vec3<f32>(2.2)), 1.0);
}
