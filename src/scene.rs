//! [`Scene`]: a scene file (the format of `scenes/*.ron`, units included) read, built in
//! code or written back, and what can be computed from it in its own units.

use std::path::{Path, PathBuf};

use vibrissa_io::resolve::{physical_whisker, resolve_model, LoadedScene, ModelFlags, Resolved};
use vibrissa_io::scene_file::SceneFile;
use vibrissa_io::units::UnitSystem;

use crate::Error;

/// The name a scene built in code or read from text goes by in messages.
pub const IN_MEMORY: &str = "<scene>";

/// A scene: the whisker, its loads, the obstacle, the sweep and method settings and the unit
/// system, as a RON scene file holds them.
///
/// [`Scene::load`] and [`Scene::from_ron`] read one (a bad value is refused naming its field
/// and line); [`Scene::new`] takes one built in code; [`Scene::to_ron`] writes it back.
/// Every computation ([`Scene::solve`], [`Scene::sweep`], [`Scene::reconstruct`]) answers in
/// the scene's units (mm, N, N mm for `units: Physical(...)`), with the numbers the command
/// line writes for the same scene.
///
/// ```
/// use vibrissa::{Scene, SceneFile, WhiskerSpec};
///
/// let mut spec = SceneFile::with_whisker(WhiskerSpec { theta: 1.0, a: 0.0, b: 0.0, k: None });
/// spec.loads.f = 1.0; // Mattiasson's cantilever, f = 1 [Table 4.1]
/// let scene = Scene::new(spec);
/// let back = Scene::from_ron(&scene.to_ron()?)?;
/// assert_eq!(back, scene);
/// let sol = scene.solve()?;
/// // Mattiasson (1981): tip deflection 0.30172 L across, 0.05643 L shortening
/// assert!((sol.tip.x - 0.30172).abs() < 1e-5 && (sol.tip.y - 0.94357).abs() < 1e-5);
/// # Ok::<(), vibrissa::Error>(())
/// ```
#[derive(Debug, Clone)]
pub struct Scene {
    /// The scene's values as a scene file holds them: change them freely, they are checked
    /// when a computation starts.
    pub spec: SceneFile,
    /// The file or text it was read from (for the line numbers of messages).
    source: Option<LoadedScene>,
}

impl PartialEq for Scene {
    /// Two scenes are equal when their values are (wherever they were read from).
    fn eq(&self, other: &Self) -> bool {
        self.spec == other.spec
    }
}

impl From<SceneFile> for Scene {
    fn from(spec: SceneFile) -> Self {
        Scene::new(spec)
    }
}

impl Scene {
    /// A scene built in code; its values are checked when a computation starts.
    pub fn new(spec: SceneFile) -> Self {
        Scene { spec, source: None }
    }

    /// Reads and checks the scene file `path`: a malformed file or a value out of range is
    /// [`Error::InvalidInput`] naming the file, line, column and field.
    pub fn load(path: impl AsRef<Path>) -> Result<Scene, Error> {
        let loaded = LoadedScene::load(path.as_ref())?;
        Ok(Scene {
            spec: loaded.file.clone(),
            source: Some(loaded),
        })
    }

    /// Reads and checks a scene from RON text (named [`IN_MEMORY`] in messages; a
    /// `points:FILE.csv` profile is relative to the working directory).
    pub fn from_ron(text: &str) -> Result<Scene, Error> {
        let path = PathBuf::from(IN_MEMORY);
        let file = SceneFile::parse(text, &path)?;
        Ok(Scene {
            spec: file.clone(),
            source: Some(LoadedScene {
                file,
                text: text.to_string(),
                path,
            }),
        })
    }

    /// The scene as pretty RON text, which [`Scene::from_ron`] reads back identically.
    pub fn to_ron(&self) -> Result<String, Error> {
        Ok(self.spec.to_ron()?)
    }

    /// The file the scene was read from, if any (a `points:FILE.csv` profile is relative to
    /// its folder).
    pub fn path(&self) -> Option<&Path> {
        self.source
            .as_ref()
            .map(|s| s.path.as_path())
            .filter(|p| *p != Path::new(IN_MEMORY))
    }

    /// The unit system of the scene's inputs and of every result ([3.16-3.19] for a physical
    /// whisker).
    pub fn units(&self) -> Result<UnitSystem, Error> {
        Ok(UnitSystem::new(physical_whisker(&self.loaded()?)?))
    }

    /// The scene as read (its text for line numbers), or as built: rendered to RON and
    /// checked.
    pub(crate) fn loaded(&self) -> Result<LoadedScene, Error> {
        match &self.source {
            Some(s) if s.file == self.spec => Ok(s.clone()),
            source => {
                let text = self.spec.to_ron()?;
                let path = source
                    .as_ref()
                    .map_or_else(|| PathBuf::from(IN_MEMORY), |s| s.path.clone());
                self.spec.validate(&text, &path)?;
                Ok(LoadedScene {
                    file: self.spec.clone(),
                    text,
                    path,
                })
            }
        }
    }

    /// The model's dimensionless values of this scene (whisker, loads, method, units), as
    /// the command line resolves a scene file given without flags.
    pub(crate) fn resolved(&self, flags: &ModelFlags) -> Result<(LoadedScene, Resolved), Error> {
        let loaded = self.loaded()?;
        let r = resolve_model(flags, Some(loaded.clone()))?;
        Ok((loaded, r))
    }
}
