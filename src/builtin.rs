//! The built-in scene of each chapter, stored as commented TOML in
//! `chapters/scenes/` so that `raylab scene --chapter N` prints exactly the
//! file a student can copy and edit.

use crate::{Scene, SceneError};

/// The TOML text of chapter `n`'s default scene (`n` in 1..=8).
pub fn scene_text(chapter: u8) -> Option<&'static str> {
    Some(match chapter {
        1 => include_str!("../chapters/scenes/chapter-1.toml"),
        2 => include_str!("../chapters/scenes/chapter-2.toml"),
        3 => include_str!("../chapters/scenes/chapter-3.toml"),
        4 => include_str!("../chapters/scenes/chapter-4.toml"),
        5 => include_str!("../chapters/scenes/chapter-5.toml"),
        6 => include_str!("../chapters/scenes/chapter-6.toml"),
        7 => include_str!("../chapters/scenes/chapter-7.toml"),
        8 => include_str!("../chapters/scenes/chapter-8.toml"),
        _ => return None,
    })
}

/// Chapter `n`'s default scene, parsed.
pub fn scene(chapter: u8) -> Result<Scene, SceneError> {
    let text = scene_text(chapter).ok_or_else(|| SceneError::Invalid {
        origin: "built-in scenes".into(),
        message: format!("there is no chapter {chapter}; chapters are 1 to 8"),
    })?;
    Scene::parse(text, &format!("built-in scene of chapter {chapter}"))
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_built_in_scene_parses() {
        for chapter in 1..=8 {
            super::scene(chapter).unwrap_or_else(|e| panic!("chapter {chapter}: {e}"));
        }
        assert!(super::scene(9).is_err());
    }
}
