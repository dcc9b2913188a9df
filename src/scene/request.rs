//! [`field`]: the one door of `platefield field` — a scene's field,
//! computed after the work estimate allows it.

use std::path::PathBuf;

use super::Scene;
use crate::error::Result;
use crate::field::Field;
use crate::work::{Estimate, Runtime};

/// What `platefield field` is asked to do.
#[derive(Debug, Clone)]
pub struct FieldRequest {
    /// The scene.
    pub scene: Scene,
    /// Where the scene came from (a file, or a name such as `scene`):
    /// physical errors name it.
    pub source: PathBuf,
    /// Progress output and the long-run guard.
    pub runtime: Runtime,
}

/// The field of the request's scene ([`Scene::compute`]), after the work
/// estimate allows it (`runtime.allow_long` lifts the limit of
/// `crate::work::LIMIT_S`). What `platefield field` and the Python
/// package's `platefield.field` compute; the report layer writes it.
///
/// ```
/// use platefield::scene::{field, FieldRequest, Scene};
/// use platefield::work::Runtime;
/// // A LineSink screw (parts squeezed onto x = 0) on 3 × 3 points.
/// let scene = Scene::from_json_str(
///     r#"{"motion": {"type": "screw", "axis": [0, 1, 0], "point": [0, 0, -0.05],
///                    "period": 0.03, "rotation": {"type": "rest_to_rest", "amplitude": 0.005}},
///         "kind": "force", "phases": 4,
///         "grid": {"x": [-0.02, 0.02], "y": [-0.02, 0.02], "n": [3, 3]}}"#,
/// )?;
/// let req = FieldRequest { scene, source: "sink scene".into(), runtime: Runtime::QUIET };
/// let f = field(&req)?;
/// assert_eq!(f.vectors.len(), 9);
/// // Squeezed onto x = 0: the force points back towards it on both sides.
/// assert!(f.vectors[0][0] > 0.0 && f.vectors[2][0] < 0.0, "{:?}", f.vectors);
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// A refused long run; a physically invalid scene (named by `source`).
pub fn field(req: &FieldRequest) -> Result<Field> {
    let scene = &req.scene;
    req.runtime.admit(
        &Estimate::new(
            "scene",
            "computing the field",
            "a smaller scene.grid.n, scene.numerics.steps_per_cycle or (force fields) scene.phases",
        )
        .plus(crate::work::field_term(
            "field",
            1.0,
            "field",
            crate::field::simulated_points(&scene.motion.to_motion(), &scene.grid) as f64,
            scene.kind,
            &scene.settings(),
        )),
    )?;
    scene
        .compute(req.runtime.progress())
        .map_err(|e| e.within(req.source.display()))
}
