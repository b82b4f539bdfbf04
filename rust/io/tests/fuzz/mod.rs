//! Property-based fuzzing's shared parts: a seeded runner whose case count
//! `SSSBAKE_FUZZ_CASES` raises for a long run (and `SSSBAKE_FUZZ_SEED`
//! varies), and mutations of valid inputs: bytes overwritten, inserted,
//! removed or cut, and JSON values replaced by hostile ones.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseResult, TestRng, TestRunner};
use serde_json::{Value, json};
use std::sync::atomic::{AtomicU64, Ordering};

/// Cases per target in the test command: a few seconds in all.
const CI_CASES: u32 = 1000;

/// A runner of `SSSBAKE_FUZZ_CASES` cases (default [`CI_CASES`]), seeded
/// by `SSSBAKE_FUZZ_SEED` (default 15) and `target`, so that a run is
/// repeatable and the targets explore apart.
fn runner(target: &str) -> TestRunner {
    let cases = std::env::var("SSSBAKE_FUZZ_CASES")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(CI_CASES);
    let seed: u64 = std::env::var("SSSBAKE_FUZZ_SEED")
        .ok()
        .and_then(|c| c.parse().ok())
        .unwrap_or(15);
    let mut bytes = [0u8; 32];
    bytes[..8].copy_from_slice(&seed.to_le_bytes());
    for (i, b) in target.bytes().enumerate() {
        bytes[8 + i % 24] ^= b;
    }
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 2000,
        ..Config::default()
    };
    TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &bytes))
}

/// Runs `test` on values of `strategy` as [`runner`] sets it up; panics
/// with the (shrunk) failing case, and says how many cases ran.
pub fn run<S: Strategy>(target: &str, strategy: S, test: impl Fn(S::Value) -> TestCaseResult) {
    let ran = AtomicU64::new(0);
    let result = runner(target).run(&strategy, |value| {
        ran.fetch_add(1, Ordering::Relaxed);
        test(value)
    });
    eprintln!("{target}: {} cases", ran.load(Ordering::Relaxed));
    if let Err(e) = result {
        panic!("{target}: {e}");
    }
}

/// One change to a byte string, at a position taken modulo its length.
#[derive(Clone, Debug)]
pub enum ByteEdit {
    /// Overwrite one byte.
    Set(usize, u8),
    /// Overwrite four bytes with a little-endian u32 (lengths, counts).
    Word(usize, u32),
    /// Insert bytes.
    Insert(usize, Vec<u8>),
    /// Remove up to this many bytes.
    Remove(usize, usize),
    /// Cut the rest off.
    Truncate(usize),
}

fn byte_edit() -> impl Strategy<Value = ByteEdit> {
    let word = prop_oneof![
        Just(0u32),
        Just(1),
        Just(4),
        Just(12),
        Just(99),
        Just(u32::MAX),
        Just(u32::MAX - 3),
        any::<u32>()
    ];
    prop_oneof![
        4 => (any::<usize>(), any::<u8>()).prop_map(|(at, b)| ByteEdit::Set(at, b)),
        2 => (any::<usize>(), word).prop_map(|(at, w)| ByteEdit::Word(at, w)),
        1 => (any::<usize>(), prop::collection::vec(any::<u8>(), 1..8))
            .prop_map(|(at, b)| ByteEdit::Insert(at, b)),
        1 => (any::<usize>(), 1usize..64).prop_map(|(at, n)| ByteEdit::Remove(at, n)),
        1 => any::<usize>().prop_map(ByteEdit::Truncate),
    ]
}

/// `base` with up to `most` byte edits.
pub fn mutated_bytes(base: Vec<u8>, most: usize) -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(byte_edit(), 1..=most).prop_map(move |edits| {
        let mut bytes = base.clone();
        for edit in edits {
            let at = |i: usize, len: usize| if len == 0 { 0 } else { i % len };
            match edit {
                ByteEdit::Set(i, b) if !bytes.is_empty() => {
                    let i = at(i, bytes.len());
                    bytes[i] = b;
                }
                ByteEdit::Word(i, w) if bytes.len() >= 4 => {
                    let i = at(i, bytes.len() - 3);
                    bytes[i..i + 4].copy_from_slice(&w.to_le_bytes());
                }
                ByteEdit::Insert(i, b) => {
                    let i = at(i, bytes.len() + 1);
                    bytes.splice(i..i, b);
                }
                ByteEdit::Remove(i, n) if !bytes.is_empty() => {
                    let i = at(i, bytes.len());
                    let end = (i + n).min(bytes.len());
                    bytes.drain(i..end);
                }
                ByteEdit::Truncate(i) => {
                    let i = at(i, bytes.len() + 1);
                    bytes.truncate(i);
                }
                _ => {}
            }
        }
        bytes
    })
}

/// JSON values a hostile file puts where a valid one has something else.
pub fn hostile_value() -> impl Strategy<Value = Value> {
    let number = prop_oneof![
        Just(json!(0)),
        Just(json!(-1)),
        Just(json!(1)),
        Just(json!(2)),
        Just(json!(3)),
        Just(json!(4)),
        Just(json!(5)),
        Just(json!(99)),
        Just(json!(255)),
        Just(json!(5120)),
        Just(json!(5121)),
        Just(json!(5123)),
        Just(json!(5125)),
        Just(json!(5126)),
        Just(json!(65535)),
        Just(json!(u32::MAX)),
        Just(json!(u64::MAX)),
        Just(json!(1u64 << 40)),
        Just(json!(0.5)),
        Just(json!(-0.5)),
        Just(json!(1e300)),
        Just(json!(-1e300)),
        Just(json!(1e-300)),
        any::<i64>().prop_map(|i| json!(i)),
    ];
    let text = prop_oneof![
        Just(json!("")),
        Just(json!("VEC3")),
        Just(json!("VEC2")),
        Just(json!("SCALAR")),
        Just(json!("MAT4")),
        Just(json!("data:application/octet-stream;base64,AAAA")),
        Just(json!("data:image/png;base64,iVBORw0KGgo=")),
        Just(json!("absent.bin")),
        Just(json!("../../../etc/passwd")),
        Just(json!("x")),
    ];
    let leaf = prop_oneof![
        6 => number,
        2 => text,
        1 => Just(Value::Null),
        1 => any::<bool>().prop_map(Value::Bool),
    ];
    leaf.prop_recursive(2, 8, 4, |inner| {
        prop_oneof![
            prop::collection::vec(inner.clone(), 0..4).prop_map(Value::Array),
            prop::collection::vec((key(), inner), 0..3)
                .prop_map(|kv| Value::Object(kv.into_iter().collect())),
        ]
    })
}

/// Keys of glTF objects and extensions, for inserting where absent.
fn key() -> impl Strategy<Value = String> {
    prop::sample::select(vec![
        "byteStride",
        "byteOffset",
        "byteLength",
        "count",
        "componentType",
        "type",
        "normalized",
        "sparse",
        "indices",
        "values",
        "bufferView",
        "buffer",
        "mode",
        "material",
        "children",
        "matrix",
        "scale",
        "rotation",
        "mesh",
        "extensions",
        "KHR_materials_volume",
        "KHR_materials_volume_scatter",
        "KHR_materials_diffuse_transmission",
        "KHR_texture_transform",
        "KHR_lights_punctual",
        "attenuationDistance",
        "attenuationColor",
        "multiscatterColor",
        "diffuseTransmissionFactor",
        "baseColorTexture",
        "TEXCOORD_1",
        "NORMAL",
        "uri",
    ])
    .prop_map(String::from)
}

/// One change to a JSON document: at the node reached by following the
/// path (each step a child chosen modulo the node's children), replace
/// it, or insert a key into it when it is an object.
#[derive(Clone, Debug)]
pub struct JsonEdit {
    path: Vec<usize>,
    key: Option<String>,
    value: Value,
}

/// `base` with up to `most` JSON edits.
pub fn mutated_json(base: Value, most: usize) -> impl Strategy<Value = Value> {
    let edit = (
        prop::collection::vec(any::<usize>(), 0..7),
        prop::option::of(key()),
        hostile_value(),
    )
        .prop_map(|(path, key, value)| JsonEdit { path, key, value });
    prop::collection::vec(edit, 1..=most).prop_map(move |edits| {
        let mut document = base.clone();
        for edit in edits {
            apply(&mut document, &edit);
        }
        document
    })
}

fn apply(document: &mut Value, edit: &JsonEdit) {
    // Walk by reading first, then edit through the JSON pointer found.
    let mut pointer = String::new();
    let mut node = &*document;
    for &step in &edit.path {
        node = match node {
            Value::Array(items) if !items.is_empty() => {
                let i = step % items.len();
                pointer.push_str(&format!("/{i}"));
                &items[i]
            }
            Value::Object(map) if !map.is_empty() => {
                let (key, value) = map.iter().nth(step % map.len()).unwrap();
                pointer.push('/');
                pointer.push_str(&key.replace('~', "~0").replace('/', "~1"));
                value
            }
            _ => break,
        };
    }
    let Some(node) = document.pointer_mut(&pointer) else {
        return;
    };
    match (&edit.key, node) {
        (Some(key), Value::Object(map)) => {
            map.insert(key.clone(), edit.value.clone());
        }
        (_, node) => *node = edit.value.clone(),
    }
}
