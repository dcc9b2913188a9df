//! [`run`]: the one door of the inverse design. It decides what runs for a
//! target and its [`DesignOptions`] — a part's pose
//! ([`crate::pose::design`]), the stacked sort of a target with classes,
//! the closed loop on a sequenced design, or the design by [`Method`] with
//! every candidate played — and returns the typed [`DesignOutcome`]; the
//! report layer and the command line only format and write it.
//! [`TargetFile::load`] reads any target file, a pose target included.
//!
//! The door sits above the design of a field ([`crate::design`]) and of a
//! pose ([`crate::pose::design`], which synthesizes through the former),
//! so that the modules import one way.

use std::path::Path;

use crate::design::closed_loop::{closed_loop, ClosedLoop};
use crate::design::method::design_by_method;
use crate::design::sort::{design_sort, SortDesign};
use crate::design::{design, Design, DesignOptions, Method, MethodDesign, PlayModel};
use crate::error::{Error, Result};
use crate::pose::design::{design_pose, PoseDesign, PoseTarget, DROPS};
use crate::request::Target;
use crate::scene::FrictionSpec;

/// A target file as read: a field to realise, or a part's pose
/// (`"field": {"kind": "pose", …}`, [`PoseTarget`]).
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
pub enum TargetFile {
    /// A target field ([`Target`]).
    Field(Target),
    /// A pose of a part.
    Pose(PoseTarget),
}

impl TargetFile {
    /// Reads the target file at `path`: a pose target when its field's
    /// kind is `pose` ([`PoseTarget::load`]), any other target otherwise
    /// ([`Target::load`]).
    ///
    /// ```
    /// use platefield::inverse::TargetFile;
    /// let file = TargetFile::load(std::path::Path::new("targets/pose_rectangle.json"))?;
    /// assert!(matches!(file, TargetFile::Pose(_)));
    /// # Ok::<(), platefield::Error>(())
    /// ```
    ///
    /// # Errors
    /// The loaders' ([`Error::Invalid`] naming the file and JSON path,
    /// [`Error::Io`]).
    pub fn load(path: &Path) -> Result<TargetFile> {
        match PoseTarget::load(path)? {
            Some(req) => Ok(TargetFile::Pose(req)),
            None => Ok(TargetFile::Field(Target::load(path)?)),
        }
    }

    /// Sets the parts' friction to `friction` (`design --friction`, named
    /// `arg` in errors), replacing the target's `friction`. A sorting
    /// target's classes and a pose target's part state their own: refused.
    ///
    /// ```
    /// use platefield::inverse::TargetFile;
    /// use platefield::scene::FrictionSpec;
    /// let mut file = TargetFile::load(std::path::Path::new("targets/sink.json"))?;
    /// file.set_friction(FrictionSpec::uniform(0.45), "--friction")?;
    /// assert_eq!(file.target().friction, Some(FrictionSpec::uniform(0.45)));
    /// let mut sort = TargetFile::load(std::path::Path::new("targets/sort_friction.json"))?;
    /// assert!(sort.set_friction(FrictionSpec::uniform(0.45), "--friction").is_err());
    /// # Ok::<(), platefield::Error>(())
    /// ```
    ///
    /// # Errors
    /// A sorting or pose target, or a friction that
    /// `FrictionSpec::validate_driven` refuses.
    pub fn set_friction(&mut self, friction: FrictionSpec, arg: &str) -> Result<()> {
        friction.validate_driven(arg)?;
        match self {
            TargetFile::Field(t) if t.classes.is_empty() => {
                t.friction = Some(friction);
                Ok(())
            }
            TargetFile::Field(_) => Err(Error::invalid(
                arg,
                "a sorting target's classes state their own friction (target.classes[i].friction)",
            )),
            TargetFile::Pose(_) => Err(Error::invalid(
                arg,
                "a pose target plays its part's friction (the part file's \"friction\")",
            )),
        }
    }

    /// The target: the field's, or the pose's (its field a sink at the
    /// pose).
    pub fn target(&self) -> &Target {
        match self {
            TargetFile::Field(t) => t,
            TargetFile::Pose(req) => &req.target,
        }
    }
}

/// What [`run`] designs, borrowed: a target field or a pose request
/// (`From` a `&Target`, a `&PoseTarget` or a `&TargetFile`).
#[derive(Debug, Clone, Copy)]
pub enum DesignRequest<'a> {
    /// A target field.
    Field(&'a Target),
    /// A pose of a part.
    Pose(&'a PoseTarget),
}

impl<'a> From<&'a Target> for DesignRequest<'a> {
    fn from(t: &'a Target) -> Self {
        DesignRequest::Field(t)
    }
}

impl<'a> From<&'a PoseTarget> for DesignRequest<'a> {
    fn from(req: &'a PoseTarget) -> Self {
        DesignRequest::Pose(req)
    }
}

impl<'a> From<&'a TargetFile> for DesignRequest<'a> {
    fn from(file: &'a TargetFile) -> Self {
        match file {
            TargetFile::Field(t) => DesignRequest::Field(t),
            TargetFile::Pose(req) => DesignRequest::Pose(req),
        }
    }
}

/// What [`run`] designed.
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
pub enum DesignOutcome {
    /// A target with classes: the sort candidates, stacked fits that sort
    /// the classes by friction ([`crate::design::sort`]), not yet played.
    Sorted(Vec<SortDesign>),
    /// The sequenced design and the closed loop run on it
    /// ([`DesignOptions::closed_loop`]).
    ClosedLoop {
        /// The open-loop sequenced design.
        design: Design,
        /// The closed loop's candidates, plays and kept schedule.
        closed_loop: ClosedLoop,
    },
    /// The design by [`DesignOptions::method`]: every candidate played
    /// against the target, one kept with a typed
    /// [`Choice`](crate::design::Choice).
    Method(MethodDesign),
    /// A pose target: one synthesized motion placed and corrected so that
    /// the part comes to rest at the pose, with [`DROPS`] played drops
    /// ([`crate::pose::design`]).
    Pose(PoseDesign),
}

impl DesignOutcome {
    /// The design by method, when that is what ran (a target without
    /// classes and no closed loop): every candidate played and the kept
    /// one.
    ///
    /// ```
    /// # use platefield::inverse::DesignOutcome;
    /// # fn kept(outcome: DesignOutcome) -> platefield::Result<platefield::design::Method> {
    /// let by_method = outcome.into_method()?;
    /// Ok(by_method.kept().method)
    /// # }
    /// ```
    ///
    /// # Errors
    /// [`Error::Invalid`] naming `method` for a sorted, closed-loop or
    /// pose design.
    pub fn into_method(self) -> Result<MethodDesign> {
        match self {
            DesignOutcome::Method(m) => Ok(m),
            _ => Err(Error::invalid(
                "method",
                "the target was sorted, closed-loop or pose designed, not designed by its method",
            )),
        }
    }
}

/// Designs `request` (a [`Target`], a [`PoseTarget`] or a [`TargetFile`])
/// as `opts` ask: the one entry point of the inverse design (see the
/// [`crate`] docs for an example).
///
/// * a pose target: [`design_pose`] with [`DROPS`] played drops (the
///   method, closed loop and classes do not apply);
/// * a target with `classes`: the stacked sort fits ([`design_sort`]);
///   only with [`Method::Auto`] or [`Method::Sequence`] and no closed loop;
/// * [`DesignOptions::closed_loop`] given: the sequenced design
///   ([`design`]) and the closed loop on it; not with a method that
///   synthesizes;
/// * otherwise the design by [`DesignOptions::method`] and
///   [`DesignOptions::synthesis`].
///
/// # Errors
/// [`Error::Invalid`] naming the option path (`method`, `closed_loop`,
/// `schedule.total_cycles`, …) or the target's JSON path; the errors of the design
/// that runs.
pub fn run<'a>(
    request: impl Into<DesignRequest<'a>>,
    opts: &DesignOptions,
) -> Result<DesignOutcome> {
    let request = request.into();
    let own = match opts.model {
        PlayModel::Own => true,
        PlayModel::Fixed(m) => m == opts.settings.model,
        PlayModel::Auto { .. } => false,
    };
    if !own {
        let other = match &request {
            DesignRequest::Pose(_) => Some("a pose target"),
            DesignRequest::Field(t) if !t.classes.is_empty() => Some("a target with classes"),
            DesignRequest::Field(_) if opts.closed_loop.is_some() => Some("the closed loop"),
            DesignRequest::Field(_) => None,
        };
        if let Some(what) = other {
            return Err(Error::invalid(
                "model",
                format!("chooses the model of a design by method; {what} is played at the settings' own model (leave it out)"),
            ));
        }
    }
    let target = match request {
        DesignRequest::Pose(req) => return Ok(DesignOutcome::Pose(design_pose(req, opts, DROPS)?)),
        DesignRequest::Field(t) => t,
    };
    let synthesizes = matches!(
        opts.method,
        Method::Synthesize | Method::Mix | Method::Mirror
    );
    if !target.classes.is_empty() {
        if opts.closed_loop.is_some() || synthesizes {
            return Err(Error::invalid(
                "method",
                "a target with classes is designed by one stacked fit of primitives (sort by friction): use method `auto` or `sequence`, without `closed_loop`",
            ));
        }
        return Ok(DesignOutcome::Sorted(design_sort(target, opts)?));
    }
    if let Some(l) = &opts.closed_loop {
        l.validate()?;
        if synthesizes {
            return Err(Error::invalid(
                "closed_loop",
                "re-fits a sequenced schedule; use it with method `sequence` (or `auto`, which then designs by sequence)",
            ));
        }
        let design = design(target, opts)?;
        let closed_loop = closed_loop(target, &design, l)?;
        return Ok(DesignOutcome::ClosedLoop {
            design,
            closed_loop,
        });
    }
    Ok(DesignOutcome::Method(design_by_method(target, opts)?))
}
