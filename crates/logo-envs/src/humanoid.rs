//! Humanoid and HumanoidStandup, as Gymnasium 1.4.0's `humanoid_v4.py`, `humanoid_v5.py`,
//! `humanoidstandup_v4.py` and `humanoidstandup_v5.py` compute them with their defaults.

use crate::env::Version;
use crate::mujoco_env::{BeforeStep, Data, ResetNoise, Task};
use crate::numpy_sum::{numpy_sum, numpy_sum_of};

/// Humanoid's observation, the same for both tasks: qpos[2:] ‖ qvel ‖ cinert ‖ cvel ‖
/// qfrc_actuator ‖ cfrc_ext, unclipped. v4 keeps every body's rows (the world's are
/// zeros) and all 23 actuator forces (376); v5 drops the world body and the free
/// joint's six forces (348).
fn observe_humanoid(version: Version, data: &Data, obs: &mut [f64]) {
    let (first_body, first_dof) = match version {
        Version::V4 => (0, 0),
        Version::V5 => (1, 6),
    };
    let parts = data.qpos()[2..]
        .iter()
        .chain(data.qvel())
        .chain(data.cinert()[first_body..].iter().flatten())
        .chain(data.cvel()[first_body..].iter().flatten())
        .chain(&data.qfrc_actuator()[first_dof..])
        .chain(data.cfrc_ext()[first_body..].iter().flatten());
    for (o, v) in obs.iter_mut().zip(parts) {
        *o = *v;
    }
}

fn humanoid_obs_dim(version: Version) -> usize {
    match version {
        Version::V4 => 22 + 23 + 14 * 10 + 14 * 6 + 23 + 14 * 6,
        Version::V5 => 22 + 23 + 13 * 10 + 13 * 6 + 17 + 13 * 6,
    }
}

/// 0.1‖ctrl‖²: the control cost of both tasks (Gymnasium squares `data.ctrl`, the action
/// as given).
fn control_cost(data: &Data) -> f64 {
    0.1 * numpy_sum_of(data.ctrl(), |a| a * a)
}

/// 5e-7‖cfrc_ext‖², at most 10: the contact cost of Humanoid-v5 and both Standups.
fn contact_cost(data: &Data) -> f64 {
    (5e-7 * numpy_sum_of(data.cfrc_ext().as_flattened(), |f| f * f)).min(10.0)
}

/// Three-dimensional humanoid walking forward. reward = 1.25 v_x(mass centre) + 5 −
/// 0.1‖a‖² (v5: the 5 only while healthy, and minus the contact cost); terminates
/// unless 1 < z < 2.
#[derive(Debug, Clone, Copy)]
pub struct Humanoid {
    pub version: Version,
}

/// x of the mass centre: Σ m_b x_b / Σ m_b over the bodies' centres of mass.
fn mass_centre_x(data: &Data) -> f64 {
    let masses = data.model().body_mass();
    let moment = masses
        .iter()
        .zip(data.xipos())
        .fold(0.0, |sum, (m, x)| sum + m * x[0]);
    moment / numpy_sum(masses)
}

impl Task for Humanoid {
    fn id(&self) -> String {
        format!("Humanoid-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "humanoid.xml"
    }
    fn frame_skip(&self) -> usize {
        5
    }
    fn obs_dim(&self) -> usize {
        humanoid_obs_dim(self.version)
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::Uniform { scale: 0.01 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        observe_humanoid(self.version, data, obs);
    }
    fn before_step(&self, data: &Data, _action: &[f64]) -> BeforeStep {
        BeforeStep {
            x: mass_centre_x(data),
            reward: 0.0,
        }
    }
    fn reward(&self, data: &Data, before: BeforeStep, dt: f64, _action: &[f64]) -> (f64, bool) {
        let z = data.qpos()[2];
        let healthy = 1.0 < z && z < 2.0;
        let forward = 1.25 * ((mass_centre_x(data) - before.x) / dt);
        let reward = match self.version {
            Version::V4 => (forward + 5.0) - control_cost(data),
            Version::V5 => {
                let healthy_reward = 5.0 * f64::from(u8::from(healthy));
                (forward + healthy_reward) - (control_cost(data) + contact_cost(data))
            }
        };
        (reward, !healthy)
    }
}

/// The humanoid lying down, paid for raising its torso: reward = z / timestep −
/// 0.1‖a‖² − the contact cost + 1. Never terminates.
#[derive(Debug, Clone, Copy)]
pub struct HumanoidStandup {
    pub version: Version,
}

impl Task for HumanoidStandup {
    fn id(&self) -> String {
        format!("HumanoidStandup-{}", self.version)
    }
    fn model_file(&self) -> &'static str {
        "humanoidstandup.xml"
    }
    fn frame_skip(&self) -> usize {
        5
    }
    fn obs_dim(&self) -> usize {
        humanoid_obs_dim(self.version)
    }
    fn reset_noise(&self) -> ResetNoise {
        ResetNoise::Uniform { scale: 0.01 }
    }
    fn observe(&self, data: &Data, obs: &mut [f64]) {
        observe_humanoid(self.version, data, obs);
    }
    fn reward(&self, data: &Data, _: BeforeStep, _dt: f64, _action: &[f64]) -> (f64, bool) {
        // Gymnasium divides by the MuJoCo timestep here, not by the env step's dt.
        let uph = data.qpos()[2] / data.model().opt().timestep;
        (
            ((uph - control_cost(data)) - contact_cost(data)) + 1.0,
            false,
        )
    }
}
