//! The shaders' double-f32 arithmetic (common.wgsl: two_sum, two_prod, df_mul, df_div, and
//! quat_largest, which must round the quaternion's fourth component as the CPU does) on this
//! device, against f64: an error-free transformation only stays one if the compiler neither
//! reassociates its sums nor rounds its products differently, which SPIR-V leaves to the driver.
//! centre_ray's precision rests on it (a glyph's centre ray to ~2⁻⁴⁴ of the eye's distance).

use tensorglyph::render::GpuContext;
use tensorglyph::render::shaders::COMMON;
use wgpu::util::DeviceExt;

const KERNEL: &str = r#"
@group(1) @binding(0) var<storage, read> input: array<vec4<f32>>;
@group(1) @binding(1) var<storage, read_write> output: array<vec4<f32>>;

@compute @workgroup_size(64)
fn cs_main(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&input) {
        return;
    }
    df_begin();
    let v = input[i];
    let s = two_sum(v.x, v.y);
    let p = two_prod(v.x, v.y);
    let q = df_div(vec2<f32>(v.x, v.z), vec2<f32>(v.y, v.w));
    let m = df_mul(vec2<f32>(v.x, v.z), vec2<f32>(v.y, v.w));
    output[4u * i] = vec4<f32>(s, p);
    output[4u * i + 1u] = vec4<f32>(q, m);
    // Three quaternion components as stored (codes in 0..2²⁰, exact in f32): input's bits.
    let code = bitcast<vec4<u32>>(v) & vec4<u32>(0xfffffu);
    let c = vec3<f32>(vec3<i32>(code.xyz) - vec3<i32>(524288)) * QUAT_STEP;
    output[4u * i + 2u] = vec4<f32>(c, quat_largest(c.x, c.y, c.z));
    output[4u * i + 3u] = vec4<f32>(0.0);
}
"#;

/// Operands over many magnitudes and signs, with lo parts below half an ulp of the hi parts.
fn operands() -> Vec<[f32; 4]> {
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..4096)
        .map(|k| {
            let a = (next() * 2.0 - 1.0) * 10f64.powf(next() * 8.0 - 4.0);
            // Half of the pairs nearly cancel in a + b, as the offsets of centre_ray do.
            let b = if k % 2 == 0 {
                -a * (1.0 + (next() - 0.5) * 1e-5)
            } else {
                (next() * 2.0 - 1.0) * 10f64.powf(next() * 8.0 - 4.0)
            };
            let (a, b) = (a as f32, b as f32);
            let lo =
                |x: f32, r: f64| (f64::from(x) * f64::EPSILON * 2f64.powi(28) * (r - 0.5)) as f32;
            [a, b, lo(a, next()), lo(b, next())]
        })
        .collect()
}

fn run(ctx: &GpuContext, input: &[[f32; 4]]) -> Vec<[f32; 4]> {
    let device = &ctx.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("double_f32 test"),
        source: wgpu::ShaderSource::Wgsl(format!("{COMMON}\n{KERNEL}").into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("double_f32 test"),
        layout: None,
        module: &module,
        entry_point: Some("cs_main"),
        compilation_options: Default::default(),
        cache: None,
    });
    let in_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(input),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = (input.len() * 4 * 16) as u64;
    let out_buf = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    // The camera only for `opaque`'s unknown 0 (eye.w = 0).
    let camera = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: &[0u8; tensorglyph::render::gpu_data::CAMERA_UNIFORM_SIZE],
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let camera_bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[wgpu::BindGroupEntry {
            binding: 0,
            resource: camera.as_entire_binding(),
        }],
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(1),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: in_buf.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: out_buf.as_entire_binding(),
            },
        ],
    });
    let mut enc = device.create_command_encoder(&Default::default());
    {
        let mut pass = enc.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &camera_bind, &[]);
        pass.set_bind_group(1, &bind, &[]);
        pass.dispatch_workgroups(input.len().div_ceil(64) as u32, 1, 1);
    }
    enc.copy_buffer_to_buffer(&out_buf, 0, &read, 0, size);
    ctx.queue.submit([enc.finish()]);
    let slice = read.slice(..);
    slice.map_async(wgpu::MapMode::Read, |r| r.expect("map"));
    ctx.wait().expect("device");
    let data = slice.get_mapped_range().expect("mapped");
    bytemuck::cast_slice::<u8, [f32; 4]>(&data).to_vec()
}

#[test]
fn double_f32_is_exact_on_this_device() {
    let ctx = match GpuContext::new() {
        Ok(ctx) => ctx,
        Err(e) => {
            assert!(
                std::env::var_os("CI").is_none(),
                "CI is set but no GPU adapter is available: {e}"
            );
            eprintln!("skipping GPU test: {e}");
            return;
        }
    };
    let input = operands();
    let out = run(&ctx, &input);
    let (mut worst_div, mut worst_mul) = (0.0f64, 0.0f64);
    for (k, v) in input.iter().enumerate() {
        let [s0, s1, p0, p1] = out[4 * k];
        let [q0, q1, m0, m1] = out[4 * k + 1];
        let (a, b) = (f64::from(v[0]), f64::from(v[1]));
        // Error-free: the pair is the exact sum and the exact product (both fit f64).
        assert_eq!(
            f64::from(s0) + f64::from(s1),
            a + b,
            "two_sum({a:e}, {b:e})"
        );
        assert_eq!(
            f64::from(p0) + f64::from(p1),
            a * b,
            "two_prod({a:e}, {b:e})"
        );
        let x = a + f64::from(v[2]);
        let y = b + f64::from(v[3]);
        let q = f64::from(q0) + f64::from(q1);
        let m = f64::from(m0) + f64::from(m1);
        worst_div = worst_div.max((q / (x / y) - 1.0).abs());
        // quat_largest as the CPU forms it (unpack_rotation: f64, rounded once).
        let [qa, qb, qc, big] = out[4 * k + 2];
        let [qa, qb, qc] = [qa, qb, qc].map(f64::from);
        let want = (1.0 - (qa * qa + qb * qb + qc * qc)).max(0.0).sqrt() as f32;
        assert_eq!(big, want, "quat_largest({qa:e}, {qb:e}, {qc:e})");
        worst_mul = worst_mul.max((m / (x * y) - 1.0).abs());
    }
    eprintln!(
        "double-f32 on {}: df_div {worst_div:.1e}, df_mul {worst_mul:.1e} relative",
        ctx.adapter_name
    );
    // ~2⁻⁴⁴ for these algorithms (a few units of 2⁻⁴⁸); f32 alone would give 6e-8.
    assert!(worst_div < 1e-12, "df_div relative error {worst_div:e}");
    assert!(worst_mul < 1e-12, "df_mul relative error {worst_mul:e}");
}
