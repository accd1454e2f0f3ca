//! Pictures of an env's state: MuJoCo's own renderer (mujoco-rs's `MjRenderer`), offscreen
//! through EGL, which Mesa's software rasteriser provides on a machine without a GPU. The
//! camera follows the robot with Gymnasium's default distances and angles. A renderer has
//! its own `MjData`: it draws a given joint state and never touches an env's simulation.

use std::sync::Arc;

use mujoco_rs::prelude::*;
use mujoco_rs::renderer::MjRenderer;

use crate::registry::EnvFactory;

/// The frame sizes a renderer accepts, per side.
pub const SIZES: std::ops::RangeInclusive<u32> = 16..=4096;

#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error("frame size {width}x{height}: each side must be {} to {} pixels", SIZES.start(), SIZES.end())]
    Size { width: u32, height: u32 },
    #[error(
        "no OpenGL context through EGL ({0}). Offscreen rendering needs an EGL driver: without \
         a GPU, Mesa's (`apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri` on Debian or \
         Ubuntu)"
    )]
    NoContext(String),
    #[error("rendering a frame: {0}")]
    Frame(String),
    #[error("a state of {qpos} + {qvel} values for a model of {nq} + {nv}")]
    State {
        qpos: usize,
        qvel: usize,
        nq: usize,
        nv: usize,
    },
}

/// The shadow map's side and the multisampling of the offscreen buffer (see [`Renderer::new`]).
const SHADOW_SIZE: i32 = 1024;
const SAMPLES: i32 = 0;

/// How much of MuJoCo's lighting a frame gets. On Mesa's software rasteriser the shadow
/// pass and the floor's mirror pass are most of a frame's cost (docs/benchmarks.md).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Look {
    /// No shadows, no reflections: ≈ 2.3× faster than `Full`.
    #[default]
    Fast,
    /// The model's own lights and materials, as Gymnasium's videos show them.
    Full,
}

/// Draws joint states of one env's model as RGB frames.
pub struct Renderer {
    data: MjData<Arc<MjModel>>,
    renderer: MjRenderer,
    width: u32,
    height: u32,
}

/// Gymnasium's default camera for `env_id` (its `DEFAULT_CAMERA_CONFIG`), tracking the
/// body it names: (body, distance, elevation in degrees).
fn camera(env_id: &str) -> (usize, f64, f64) {
    let task = crate::dense_id(env_id);
    match task.split('-').next().unwrap_or(task) {
        // Gymnasium tracks body 2 (the thigh); its subtree's centre leaves the torso
        // out of a square frame, so the whole robot's (body 1) is tracked instead.
        "Hopper" | "Walker2d" => (1, 3.0, -20.0),
        "HalfCheetah" => (1, 4.0, -20.0),
        _ => (0, 4.1225, -20.0),
    }
}

impl Renderer {
    /// A renderer of `width` × `height` frames for the env `factory` builds.
    pub fn new(
        factory: &EnvFactory,
        width: u32,
        height: u32,
        look: Look,
    ) -> Result<Self, RenderError> {
        if !SIZES.contains(&width) || !SIZES.contains(&height) {
            return Err(RenderError::Size { width, height });
        }
        let mut model = (**factory
            .model()
            .map_err(|e| RenderError::Frame(e.to_string()))?)
        .clone();
        // The offscreen buffer must hold the frame (the MJCF files ask for 640 × 480).
        let global = &mut model.vis_mut().global;
        global.offwidth = global.offwidth.max(width as i32);
        global.offheight = global.offheight.max(height as i32);
        // MuJoCo's defaults (a 4096² shadow map, 4× multisampling) cost ≈ 0.15-0.25 s a
        // frame on Mesa's software rasteriser; a 1024² map without multisampling keeps the
        // shadows and reflections at a quarter of that (docs/benchmarks.md).
        let quality = &mut model.vis_mut().quality;
        quality.shadowsize = quality.shadowsize.min(SHADOW_SIZE);
        quality.offsamples = SAMPLES;
        if look == Look::Fast {
            model.mat_reflectance_mut().fill(0.0);
            model.light_castshadow_mut().fill(false);
        }
        let model = Arc::new(model);
        let (body, distance, elevation) = camera(&factory.spec().id);
        let mut camera = MjvCamera::new_tracking(body);
        camera.distance = distance;
        camera.elevation = elevation;
        camera.azimuth = 90.0;
        let renderer = MjRenderer::builder()
            .width(width)
            .height(height)
            .camera(camera)
            .build(&model)
            .map_err(|e| RenderError::NoContext(e.to_string()))?;
        Ok(Self {
            data: MjData::new(model),
            renderer,
            width,
            height,
        })
    }

    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The frame of joint state (`qpos`, `qvel`) (an env's [`crate::Env::state`]): RGB,
    /// rows top to bottom, `width × height × 3` bytes.
    pub fn render(&mut self, qpos: &[f64], qvel: &[f64]) -> Result<&[u8], RenderError> {
        let (nq, nv) = (self.data.qpos().len(), self.data.qvel().len());
        if (qpos.len(), qvel.len()) != (nq, nv) {
            return Err(RenderError::State {
                qpos: qpos.len(),
                qvel: qvel.len(),
                nq,
                nv,
            });
        }
        self.data.qpos_mut().copy_from_slice(qpos);
        self.data.qvel_mut().copy_from_slice(qvel);
        self.data.forward();
        let frame = |e: mujoco_rs::renderer::RendererError| RenderError::Frame(e.to_string());
        self.renderer.sync_data(&mut self.data).map_err(frame)?;
        self.renderer.render().map_err(frame)?;
        self.renderer
            .rgb_flat()
            .ok_or_else(|| RenderError::Frame("RGB rendering is off".into()))
    }
}
