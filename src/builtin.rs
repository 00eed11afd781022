//! The built-in scene of each chapter, stored as commented TOML in
//! each chapter folder's `scene.toml` so that `raylab scene --chapter N` prints exactly the
//! file a student can copy and edit.

use crate::{Scene, SceneError};

/// The TOML text of chapter `n`'s default scene.
pub fn scene_text(chapter: u8) -> Option<&'static str> {
    crate::chapters::chapter(chapter).map(|info| info.scene)
}

/// Chapter `n`'s default scene, parsed.
pub fn scene(chapter: u8) -> Result<Scene, SceneError> {
    let text = scene_text(chapter).ok_or_else(|| SceneError::Invalid {
        origin: "built-in scenes".into(),
        message: format!(
            "there is no chapter {chapter}; chapters are 1 to {}",
            crate::chapters::LAST_CHAPTER
        ),
    })?;
    Scene::parse(text, &format!("built-in scene of chapter {chapter}"))
}

#[cfg(test)]
mod tests {
    #[test]
    fn every_built_in_scene_parses() {
        for info in crate::chapters::CHAPTERS {
            super::scene(info.number).unwrap_or_else(|e| panic!("chapter {}: {e}", info.number));
        }
        assert!(super::scene(crate::chapters::LAST_CHAPTER + 1).is_err());
    }
}
