// Per-pixel noise shared by techniques: integer hashes (PCG) and low-discrepancy sequences.
// Deterministic: the same pixel and frame always give the same values.

// True when the technique's output is accumulated over frames (`temporal = true`,
// crates/ao-passes/src/temporal_option.rs sets it): its noise then follows the frame index, so
// the running mean averages over noise realisations. False (the default): the same noise
// every frame, as without accumulation.
override TEMPORAL_NOISE: bool = false;

// The frame a technique's noise is drawn for: `frame_index` under TEMPORAL_NOISE, else 0.
fn noise_frame(frame_index: u32) -> u32 {
    return select(0u, frame_index, TEMPORAL_NOISE);
}

fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform float in [0, 1) from a pixel and a salt.
fn hash_pixel(p: vec2<u32>, salt: u32) -> f32 {
    return f32(pcg_hash(p.x ^ pcg_hash(p.y ^ pcg_hash(salt))) >> 8u) / 16777216.0;
}

// The 4x4 interleaved (Bayer-ordered) index of a pixel, 0..15.
fn interleave_4x4(p: vec2<u32>) -> u32 {
    let x = p.x & 3u;
    let y = p.y & 3u;
    let bayer = array<u32, 16>(0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);
    return bayer[y * 4u + x];
}

// Radical inverse in base 2 (van der Corput).
fn radical_inverse_2(i: u32) -> f32 {
    return f32(reverseBits(i)) * 2.3283064365386963e-10;
}

// Radical inverse in base 3.
fn radical_inverse_3(i: u32) -> f32 {
    var n = i;
    var inv = 1.0 / 3.0;
    var f = inv;
    var r = 0.0;
    for (var k = 0u; k < 20u && n > 0u; k = k + 1u) {
        r = r + f32(n % 3u) * f;
        n = n / 3u;
        f = f * inv;
    }
    return r;
}

// Point i of the 2D Halton sequence (bases 2, 3).
fn halton_2_3(i: u32) -> vec2<f32> {
    return vec2<f32>(radical_inverse_2(i), radical_inverse_3(i));
}
