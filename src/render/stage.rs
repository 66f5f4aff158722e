//! A scene and the structure built over it: what every render, inspection and AOV pass takes.

use crate::accel::{Accel, AccelChoice};
use crate::scene::Scene;
use std::sync::{Arc, Weak};

/// A scene with its acceleration structure, built once ([`Stage::new`]) and shared by clones.
///
/// The scene inside changes only through [`Stage::restyle`] (colours, tints, the light), which
/// keeps the structure: the primitives it was built over cannot change under it. To change them,
/// build a new stage.
#[derive(Clone, Debug)]
pub struct Stage {
    scene: Arc<Scene>,
    accel: Arc<Accel>,
}

impl Stage {
    /// Builds the structure `choice` names over `scene` (now, on the calling thread) and adds to
    /// the scene's warnings what the build left out as copies ([`Accel::copies_warning`]).
    pub fn new(mut scene: Scene, choice: AccelChoice) -> Self {
        let accel = Accel::for_scene(&scene, choice);
        scene.warnings.extend(accel.copies_warning(&scene));
        Self {
            scene: Arc::new(scene),
            accel: Arc::new(accel),
        }
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The structure over the scene's primitives.
    pub fn accel(&self) -> &Accel {
        &self.accel
    }

    /// A handle naming this stage's structure without keeping it: [`Weak::ptr_eq`] for the
    /// stages that share it (a restyle keeps it), never for another stage's, even once this
    /// one is dropped (the handle holds its allocation). What a frame's cracks depend on.
    pub fn structure_handle(&self) -> Weak<Accel> {
        Arc::downgrade(&self.accel)
    }

    /// Changes what does not move a primitive (colours, tints, the light), keeping the structure.
    /// The scene is copied first if another stage shares it.
    pub fn restyle(&mut self, restyle: impl FnOnce(&mut Scene)) {
        let primitives = self.scene.len();
        restyle(Arc::make_mut(&mut self.scene));
        assert_eq!(
            self.scene.len(),
            primitives,
            "a restyle keeps the primitives"
        );
    }
}

/// The structure raylab chooses for the scene ([`AccelChoice::Auto`]).
impl From<Scene> for Stage {
    fn from(scene: Scene) -> Self {
        Self::new(scene, AccelChoice::Auto)
    }
}
