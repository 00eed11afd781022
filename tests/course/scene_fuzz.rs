//! Randomly mutated scene files never make the loader panic: every outcome
//! is a scene or an error message.

use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

/// Small edits a careless hand or a broken file could make.
#[derive(Debug, Clone)]
enum Mutation {
    DeleteByte(usize),
    InsertByte(usize, u8),
    ReplaceByte(usize, u8),
    Truncate(usize),
    SwapNumber(usize, &'static str),
}

const NUMBERS: &[&str] = &[
    "0",
    "-0.0",
    "-1",
    "1e39",
    "-1e39",
    "nan",
    "inf",
    "-inf",
    "1e-45",
    "4294967296",
    "-5",
    "0.0",
    "1e30",
];

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        any::<usize>().prop_map(Mutation::DeleteByte),
        (any::<usize>(), any::<u8>()).prop_map(|(at, b)| Mutation::InsertByte(at, b)),
        (
            any::<usize>(),
            prop::sample::select(b"[]{}=\",.#\n0-e".to_vec())
        )
            .prop_map(|(at, b)| Mutation::ReplaceByte(at, b)),
        any::<usize>().prop_map(Mutation::Truncate),
        (any::<usize>(), prop::sample::select(NUMBERS))
            .prop_map(|(at, n)| Mutation::SwapNumber(at, n)),
    ]
}

fn apply(text: &str, mutation: &Mutation) -> Vec<u8> {
    let mut bytes = text.as_bytes().to_vec();
    let len = bytes.len();
    if len == 0 {
        // Earlier mutations may have truncated the text to nothing.
        return bytes;
    }
    match *mutation {
        Mutation::DeleteByte(at) => {
            bytes.remove(at % len);
        }
        Mutation::InsertByte(at, b) => bytes.insert(at % (len + 1), b),
        Mutation::ReplaceByte(at, b) => bytes[at % len] = b,
        Mutation::Truncate(at) => bytes.truncate(at % len),
        Mutation::SwapNumber(at, number) => {
            // Replace the number that starts at or after `at` with `number`.
            let start = (at % len..len).find(|&i| {
                bytes[i].is_ascii_digit() && (i == 0 || !bytes[i - 1].is_ascii_alphanumeric())
            });
            if let Some(start) = start {
                let end = (start..len)
                    .find(|&i| !(bytes[i].is_ascii_digit() || bytes[i] == b'.'))
                    .unwrap_or(len);
                bytes.splice(start..end, number.bytes());
            }
        }
    }
    bytes
}

proptest! {
    // Failing cases are kept in the .proptest-regressions file beside this
    // one, as before the tests were grouped (proptest's default would use
    // tests/proptest-regressions/, since this folder has a main.rs).
    #![proptest_config(ProptestConfig {
        cases: 400,
        failure_persistence: Some(Box::new(FileFailurePersistence::WithSource("proptest-regressions"))),
        // The same cases on every run: a test must not pass or fail by the
        // draw (proptest's f32 sampler has a debug assertion that a rare
        // draw trips, as a CI run met).
        rng_seed: proptest::test_runner::RngSeed::Fixed(17),
        ..ProptestConfig::default()
    })]

    #[test]
    fn mutated_scenes_load_or_fail_cleanly(
        chapter in 1u8..=8,
        mutations in prop::collection::vec(mutation(), 1..4),
    ) {
        let mut text = raylab::builtin::scene_text(chapter).expect("built-in").to_string();
        for m in &mutations {
            text = String::from_utf8_lossy(&apply(&text, m)).into_owned();
        }
        match raylab::Scene::parse(&text, "fuzzed scene") {
            Ok(scene) => {
                // Whatever loads must also render without NaN, at a tiny size.
                let settings = raylab::RenderSettings { width: 4, height: 3, samples: 1, ..scene.render };
                let rendered = raylab::render(&scene, chapter, &settings, None).expect("renders");
                prop_assert_eq!(rendered.rays.non_finite_samples, 0);
            }
            Err(error) => prop_assert!(error.to_string().starts_with("fuzzed scene")),
        }
    }
}
