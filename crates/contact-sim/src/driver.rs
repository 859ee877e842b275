//! The sweep's entry (thesis Fig. 5.6): the inputs checked, the free whisker under the flow
//! and its exact first touch, then the contact branch handed to the law of the contact
//! ([`crate::contact_law::ContactLaw`]): frictionless ([`mod@crate::sweep`]) or Coulomb friction
//! ([`crate::friction`], any obstacle and motion).

use crate::error::Result;
use crate::first_contact::{first_touch, free_tip};
use crate::motion::Frame;
use crate::profile::Profile;
use crate::sweep::{check_settings, frictionless, SweepProgress, SweepResult, SweepSettings};
use crate::touch_scan::first_touch_along;
use beam_model::shot::Integration;
use beam_model::{FluidLoad, Loads, Whisker};

/// Sweeps a whisker under the fluid load `flow` past `profile` (thesis Fig. 5.6).
pub fn sweep(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
) -> Result<SweepResult> {
    sweep_with_progress(whisker, flow, profile, settings, &mut |_| {})
}

/// [`sweep`] reporting its progress to `progress` (e.g. for a progress bar).
pub fn sweep_with_progress(
    whisker: &Whisker,
    flow: FluidLoad,
    profile: &Profile,
    settings: &SweepSettings,
    progress: &mut dyn FnMut(SweepProgress),
) -> Result<SweepResult> {
    whisker.validate()?;
    Loads::fluid(flow.q, flow.alpha).validate()?;
    check_settings(settings, flow)?;
    settings.motion.validate()?;
    profile.check_reachable_convex()?;
    let frame = settings.motion.frame().unwrap_or_default();
    let graph_translated =
        settings.motion.frame() == Some(Frame::Translate) && !profile.is_closed();
    let integration = Integration::adaptive(settings.integration_tol);
    // The free whisker under the flow, then its exact first touch: on the graph's right
    // flank for a translation, along the motion otherwise ([`crate::touch_scan`]).
    let phi1 = free_tip(whisker, flow, settings.integration_tol, &integration)?;
    if let crate::motion::BaseMotion::Path(path) = &settings.motion {
        let scene = (whisker, flow, profile);
        if let Some(mu) = settings.contact_law.friction() {
            return crate::friction::sweep_path(scene, settings, path, (phi1, mu), progress);
        }
        return crate::path::sweep_path(scene, settings, path, phi1, progress);
    }
    let touch = if graph_translated {
        first_touch(whisker, flow, phi1, profile, settings.integration_tol)?
    } else {
        let tol = settings.integration_tol;
        let start = settings.motion.start();
        first_touch_along(whisker, flow, (phi1, tol), profile, frame, start)?
    };
    profile.convex_at(touch.t)?;
    if let Some(mu) = settings.contact_law.friction() {
        let at = (phi1, &touch);
        return crate::friction::sweep(whisker, flow, profile, settings, at, mu, progress);
    }
    frictionless(whisker, flow, profile, settings, (phi1, touch), progress)
}
