//! Videos of policies: episodes drawn offscreen by MuJoCo's renderer
//! (`logo_envs::render`), each frame captioned in its corner with the step, the dense and
//! sparse returns so far and the distance moved, and encoded as H.264 MP4 by the system's
//! `ffmpeg` (docs/architecture.md says why ffmpeg).

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};

use anyhow::{Context, Result, bail, ensure};
use clap::Args;
use logo_algo::episode::{Episode, run_episode_with};
use logo_envs::render::{Look, Renderer};
use logo_envs::{Env, EnvFactory};
use plotters::prelude::*;

/// `--video` and its frame options, shared by `logo eval`, `logo rollout` and
/// `logo train --video-every`.
#[derive(Args, Clone, Debug)]
pub struct VideoArgs {
    /// Record the episodes into this MP4 file.
    #[arg(long)]
    pub video: Option<PathBuf>,
    /// Frame width in pixels (even).
    #[arg(long, default_value_t = 480)]
    pub width: u32,
    /// Frame height in pixels (even).
    #[arg(long, default_value_t = 480)]
    pub height: u32,
    /// Frames per second (default: the env's, 1 / dt).
    #[arg(long)]
    pub fps: Option<f64>,
    /// `full`: the model's shadows and reflections, as Gymnasium's videos have them
    /// (≈ 2.3× slower to render on a CPU).
    #[arg(long, value_enum, default_value_t = VideoLook::Fast)]
    pub video_look: VideoLook,
}

/// `--video-look`.
#[derive(clap::ValueEnum, Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum VideoLook {
    /// No shadows, no reflections.
    #[default]
    Fast,
    /// Shadows and the floor's reflections.
    Full,
}

/// The frame size, rate and look of a recording.
#[derive(Debug, Clone, Copy)]
pub struct Frames {
    pub width: u32,
    pub height: u32,
    pub fps: Option<f64>,
    pub look: VideoLook,
}

impl VideoArgs {
    pub fn frames(&self) -> Frames {
        Frames {
            width: self.width,
            height: self.height,
            fps: self.fps,
            look: self.video_look,
        }
    }
}

/// An MP4 being written: frames go to ffmpeg's stdin as raw RGB.
pub struct Video {
    path: PathBuf,
    renderer: Renderer,
    ffmpeg: Child,
    stdin: Option<ChildStdin>,
    frame: Vec<u8>,
    frames: usize,
}

impl Video {
    /// Starts `path` for the env `factory` builds.
    pub fn start(path: &Path, factory: &EnvFactory, frames: Frames) -> Result<Self> {
        let (width, height) = (frames.width, frames.height);
        ensure!(
            width % 2 == 0 && height % 2 == 0,
            "--width {width} --height {height}: H.264 needs even frame sizes"
        );
        ensure!(
            path.extension().and_then(|e| e.to_str()) == Some("mp4"),
            "--video {}: the file must end in .mp4",
            path.display()
        );
        let fps = frames.fps.unwrap_or(1.0 / factory.spec().dt);
        ensure!(
            fps.is_finite() && (1.0..=1000.0).contains(&fps),
            "--fps {fps}: expected 1 to 1000 frames per second"
        );
        // A path that cannot be written fails here, not after the episodes.
        std::fs::File::create(path).with_context(|| format!("--video {}", path.display()))?;
        let look = match frames.look {
            VideoLook::Fast => Look::Fast,
            VideoLook::Full => Look::Full,
        };
        let renderer = Renderer::new(factory, width, height, look)?;
        let mut ffmpeg = Command::new("ffmpeg")
            .args([
                "-loglevel",
                "error",
                "-y",
                "-f",
                "rawvideo",
                "-pix_fmt",
                "rgb24",
            ])
            .args(["-s", &format!("{width}x{height}"), "-r", &format!("{fps}")])
            .args(["-i", "-", "-an", "-c:v", "libx264", "-pix_fmt", "yuv420p"])
            .args(["-preset", "veryfast"])
            .args([
                "-metadata",
                &format!("comment=logo-rl: {}, mean action", factory.spec().id),
            ])
            .arg(path)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| match e.kind() {
                std::io::ErrorKind::NotFound => anyhow::anyhow!(
                    "--video: ffmpeg was not found on PATH; install it (`apt-get install ffmpeg` \
                     on Debian or Ubuntu)"
                ),
                _ => anyhow::anyhow!("--video: starting ffmpeg: {e}"),
            })?;
        let stdin = ffmpeg.stdin.take();
        Ok(Self {
            path: path.to_path_buf(),
            renderer,
            ffmpeg,
            stdin,
            frame: Vec::new(),
            frames: 0,
        })
    }

    /// One frame of `env`'s state, with `caption` in its top-left corner.
    pub fn frame(&mut self, env: &dyn Env, caption: &str) -> Result<()> {
        let (qpos, qvel) = env.state();
        let rgb = self.renderer.render(qpos, qvel)?;
        self.frame.clear();
        self.frame.extend_from_slice(rgb);
        let (width, height) = self.renderer.size();
        caption_corner(&mut self.frame, (width, height), caption)?;
        let stdin = self.stdin.as_mut().expect("open until finish");
        if let Err(e) = stdin.write_all(&self.frame) {
            let reason = self.ffmpeg_error();
            bail!("{}: ffmpeg stopped ({e}){reason}", self.path.display());
        }
        self.frames += 1;
        Ok(())
    }

    fn ffmpeg_error(&mut self) -> String {
        let _ = self.ffmpeg.wait();
        let mut text = String::new();
        if let Some(mut stderr) = self.ffmpeg.stderr.take() {
            let _ = std::io::Read::read_to_string(&mut stderr, &mut text);
        }
        match text.trim() {
            "" => String::new(),
            t => format!(": {t}"),
        }
    }

    /// A frame of an episode in progress, captioned with `label`, the step, both returns
    /// so far and the distance moved.
    pub fn episode_frame(&mut self, env: &dyn Env, label: &str, e: &Episode) -> Result<()> {
        let caption = format!(
            "{label}step {} | dense {:.1} | return {:.1} | x {:+.2} m",
            e.length, e.dense_return, e.return_, e.moved
        );
        self.frame(env, &caption)
    }

    /// Closes the file; the number of frames written.
    pub fn finish(mut self) -> Result<usize> {
        drop(self.stdin.take());
        let status = self.ffmpeg.wait().context("waiting for ffmpeg")?;
        if !status.success() {
            let reason = self.ffmpeg_error();
            bail!("{}: ffmpeg failed ({status}){reason}", self.path.display());
        }
        Ok(self.frames)
    }
}

/// Writes `text` on a dark band in the corner of an RGB frame.
fn caption_corner(rgb: &mut [u8], (width, height): (u32, u32), text: &str) -> Result<()> {
    logo_lab::plot::register_font();
    let root = BitMapBackend::with_buffer(rgb, (width, height)).into_drawing_area();
    let err = |e: DrawingAreaErrorKind<_>| anyhow::anyhow!("drawing the caption: {e:?}");
    let size = (height as f64 / 32.0).clamp(9.0, 28.0);
    let font = ("sans-serif", size).into_font().color(&WHITE);
    let (w, h) = root.estimate_text_size(text, &font).map_err(err)?;
    root.draw(&Rectangle::new(
        [(0, 0), (w as i32 + 12, h as i32 + 8)],
        BLACK.mix(0.55).filled(),
    ))
    .map_err(err)?;
    root.draw(&Text::new(text, (6, 4), font)).map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}

/// Runs one episode from `reset(seed)` acting with `act`, a frame after every step into
/// `video`, captioned with `label`, the step, both returns so far and the distance moved.
pub fn record_episode(
    video: &mut Video,
    env: &mut dyn Env,
    seed: u64,
    label: &str,
    act: impl FnMut(&[f64]) -> Vec<f64>,
) -> Result<Episode> {
    run_episode_with(env, seed, act, |env, e: &Episode| {
        video.episode_frame(env, label, e)
    })
}
