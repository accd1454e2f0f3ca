//! Generated corruptions of a file's bytes, shared by the fuzz tests of every loader
//! (`logo-data/tests/fuzz.rs`, and `logo-algo/tests/fuzz.rs` includes this file by path).

use std::panic::{AssertUnwindSafe, catch_unwind};

use proptest::prelude::*;

pub fn config() -> ProptestConfig {
    let cases = std::env::var("PROPTEST_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(64);
    ProptestConfig {
        cases,
        failure_persistence: None,
        ..ProptestConfig::default()
    }
}

/// One corruption of a file's bytes.
#[derive(Debug, Clone)]
pub enum Mutation {
    /// Keep this fraction (per mille) of the file.
    Truncate(u16),
    /// Flip one bit at a position (per million of the length, or in the first 4 KiB:
    /// the headers).
    Flip { at: u32, header: bool, bit: u8 },
    /// Overwrite 8 bytes with a special value.
    Overwrite { at: u32, header: bool, value: u8 },
}

const SPECIAL: [[u8; 8]; 9] = [
    0u64.to_le_bytes(),
    1u64.to_le_bytes(),
    u64::MAX.to_le_bytes(),
    (u32::MAX as u64).to_le_bytes(),
    (i64::MAX as u64).to_le_bytes(),
    f64::NAN.to_bits().to_le_bytes(),
    f64::INFINITY.to_bits().to_le_bytes(),
    f64::NEG_INFINITY.to_bits().to_le_bytes(),
    1e308f64.to_bits().to_le_bytes(),
];

pub fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (0u16..1000).prop_map(Mutation::Truncate),
        (0u32..1_000_000, any::<bool>(), 0u8..8).prop_map(|(at, header, bit)| Mutation::Flip {
            at,
            header,
            bit
        }),
        (0u32..1_000_000, any::<bool>(), 0u8..SPECIAL.len() as u8)
            .prop_map(|(at, header, value)| Mutation::Overwrite { at, header, value }),
    ]
}

pub fn apply(bytes: &[u8], mutations: &[Mutation]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    let position = |at: u32, header: bool, len: usize| {
        let span = if header { len.min(4096) } else { len };
        (at as usize * span) / 1_000_000
    };
    for m in mutations {
        if out.is_empty() {
            break;
        }
        match *m {
            Mutation::Truncate(keep) => out.truncate(out.len() * keep as usize / 1000),
            Mutation::Flip { at, header, bit } => {
                let i = position(at, header, out.len());
                out[i] ^= 1 << bit;
            }
            Mutation::Overwrite { at, header, value } => {
                let i = position(at, header, out.len());
                let end = (i + 8).min(out.len());
                out[i..end].copy_from_slice(&SPECIAL[value as usize][..end - i]);
            }
        }
    }
    out
}

/// Runs `load`; a panic fails the case with its message.
pub fn no_panic<T>(what: &str, load: impl FnOnce() -> T) -> Result<T, TestCaseError> {
    catch_unwind(AssertUnwindSafe(load)).map_err(|e| {
        let message = e
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| e.downcast_ref::<&str>().map(|s| s.to_string()))
            .unwrap_or_default();
        TestCaseError::fail(format!("{what} panicked: {message}"))
    })
}
