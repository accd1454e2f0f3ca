//! Videos of policies, decoded by ffmpeg/ffprobe: one frame per step at the stated size,
//! frames that change as the robot moves and that differ between two policies; clear
//! errors for bad input and for a missing renderer or encoder; and `--video-every`, which
//! leaves a run's metrics and checkpoint bit-identical. Needs ffmpeg and an EGL driver
//! (Mesa's, `scripts/test.sh` installs them on CI); skipped without them unless
//! LOGO_REQUIRE_VIDEO is set (CI sets it).

use logo_testkit::{Logo, Tiny, scratch};
use std::path::Path;
use std::process::{Command, Output};

fn have(program: &str) -> bool {
    Command::new(program).arg("-version").output().is_ok()
}

fn available() -> bool {
    let egl = [
        "/usr/lib/x86_64-linux-gnu/libEGL.so.1",
        "/usr/lib/libEGL.so.1",
    ]
    .iter()
    .any(|p| Path::new(p).exists());
    let ok = egl && have("ffmpeg") && have("ffprobe");
    if !ok {
        assert!(
            std::env::var_os("LOGO_REQUIRE_VIDEO").is_none(),
            "LOGO_REQUIRE_VIDEO is set but ffmpeg or libEGL is missing (apt-get install ffmpeg \
             libegl1 libegl-mesa0 libgl1-mesa-dri)"
        );
        eprintln!("skipped: no ffmpeg or no libEGL");
    }
    ok
}

fn cli() -> Logo {
    Logo::new(env!("CARGO_BIN_EXE_logo"))
}

fn logo(args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut command = cli().command();
    command.args(args).envs(env.iter().copied());
    command.output().unwrap()
}

fn succeed(args: &[&str]) -> String {
    cli().succeed(args)
}

fn failure(args: &[&str], env: &[(&str, &str)]) -> String {
    let out = logo(args, env);
    assert!(!out.status.success(), "logo {} succeeded", args.join(" "));
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{stderr}");
    stderr
}

/// Every frame of `video` as RGB bytes, and its (width, height) per ffprobe.
fn decode(video: &Path) -> (Vec<Vec<u8>>, (usize, usize)) {
    let probe = Command::new("ffprobe")
        .args(["-v", "error", "-select_streams", "v:0", "-count_frames"])
        .args([
            "-show_entries",
            "stream=width,height,nb_read_frames",
            "-of",
            "csv=p=0",
        ])
        .arg(video)
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&probe.stdout);
    let fields: Vec<usize> = text.trim().split(',').map(|f| f.parse().unwrap()).collect();
    let (width, height, count) = (fields[0], fields[1], fields[2]);
    let raw = Command::new("ffmpeg")
        .args(["-v", "error", "-i"])
        .arg(video)
        .args(["-f", "rawvideo", "-pix_fmt", "rgb24", "-"])
        .output()
        .unwrap()
        .stdout;
    let frames: Vec<Vec<u8>> = raw.chunks(width * height * 3).map(<[u8]>::to_vec).collect();
    assert_eq!(frames.len(), count, "ffprobe's and ffmpeg's frame counts");
    (frames, (width, height))
}

/// Mean absolute difference of two frames' lower halves (below any caption).
fn difference(a: &[u8], b: &[u8]) -> f64 {
    let half = a.len() / 2;
    let sum: u64 = a[half..]
        .iter()
        .zip(&b[half..])
        .map(|(x, y)| x.abs_diff(*y) as u64)
        .sum();
    sum as f64 / half as f64
}

/// The steps `logo rollout` printed for its one episode.
fn steps(stdout: &str) -> usize {
    let at = stdout.find("episode 0:").unwrap();
    stdout[at + 10..]
        .split_whitespace()
        .next()
        .unwrap()
        .parse()
        .unwrap()
}

#[test]
fn a_rollout_video_has_a_frame_per_step_that_moves_and_differs_between_policies() {
    if !available() {
        return;
    }
    let dir = scratch("rollout");
    let video = |policy: &str| {
        let path = dir.join(format!("{policy}.mp4"));
        let printed = succeed(&[
            "rollout",
            "--env",
            "Hopper-v4",
            "--episodes",
            "1",
            "--seed",
            "3",
            "--policy",
            policy,
            "--video",
            path.to_str().unwrap(),
            "--width",
            "96",
            "--height",
            "64",
        ]);
        (decode(&path), steps(&printed))
    };
    let ((zero, size), zero_steps) = video("zero");
    assert_eq!(size, (96, 64));
    assert_eq!(zero.len(), zero_steps, "one frame per step");
    let ((random, _), random_steps) = video("random");
    assert_eq!(random.len(), random_steps);
    // The hopper tips over with zero actions: its last frame is not its first.
    assert!(difference(&zero[0], &zero[zero.len() - 1]) > 2.0);
    // Random actions fall another way: at the same step, other pictures.
    let k = zero.len().min(random.len()) - 1;
    assert!(difference(&zero[k], &random[k]) > 1.0, "step {k}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_video_requests_are_one_line_errors() {
    if !available() {
        return;
    }
    let dir = scratch("errors");
    let rollout = |video: &str, extra: &[&str], env: &[(&str, &str)]| {
        let mut args = vec![
            "rollout",
            "--env",
            "Hopper-v4",
            "--episodes",
            "1",
            "--video",
            video,
        ];
        args.extend(extra);
        failure(&args, env)
    };
    let err = rollout("/no/such/folder/a.mp4", &[], &[]);
    assert!(err.contains("--video /no/such/folder/a.mp4"), "{err}");
    let ok = dir.join("a.mp4");
    let ok = ok.to_str().unwrap();
    let err = rollout(ok, &["--width", "97"], &[]);
    assert!(err.contains("even frame sizes"), "{err}");
    let err = rollout(ok, &["--width", "100000"], &[]);
    assert!(err.contains("each side must be 16 to 4096 pixels"), "{err}");
    let err = rollout(dir.join("a.avi").to_str().unwrap(), &[], &[]);
    assert!(err.contains("must end in .mp4"), "{err}");
    // No ffmpeg on PATH, and no EGL driver for the renderer: each names what to install.
    let err = rollout(ok, &[], &[("PATH", "/nonexistent")]);
    assert!(err.contains("apt-get install ffmpeg"), "{err}");
    let err = rollout(
        ok,
        &[],
        &[("__EGL_VENDOR_LIBRARY_FILENAMES", "/nonexistent.json")],
    );
    assert!(err.contains("libegl-mesa0"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn video_every_leaves_the_runs_numbers_bit_identical() {
    if !available() {
        return;
    }
    let dir = scratch("every");
    let config = Tiny::logo()
        .lbfgs(3)
        .with("iterations = 4\nsamples_per_iter = 400")
        .write(&dir.join("tiny.toml"));
    let train = |name: &str, extra: &[&str]| {
        let out = dir.join(name);
        let more = [&["--no-tensorboard"], extra].concat();
        let printed = cli().train(&config, &out, &more);
        (out, printed)
    };
    let (plain, _) = train("plain", &[]);
    let (filmed, printed) = train("filmed", &["--video-every", "2"]);
    assert!(printed.contains("iteration-00002.mp4"), "{printed}");
    for k in [2, 4] {
        let (frames, size) = decode(&filmed.join(format!("videos/iteration-{k:05}.mp4")));
        assert_eq!(size, (480, 480));
        assert!(!frames.is_empty());
    }
    assert!(!filmed.join("videos/iteration-00001.mp4").exists());
    assert_eq!(
        logo_testkit::metrics_without_timings(&plain),
        logo_testkit::metrics_without_timings(&filmed)
    );
    let bytes = |dir: &Path| std::fs::read(dir.join("checkpoint.safetensors")).unwrap();
    assert!(bytes(&plain) == bytes(&filmed), "the checkpoints differ");
    // A video of this checkpoint on an env of other dimensions, or of no episode, is
    // refused before anything is written.
    let checkpoint = plain.join("checkpoint.safetensors");
    let video = dir.join("refused.mp4");
    let eval = |extra: &[&str]| {
        let mut args = vec!["eval", "--checkpoint", checkpoint.to_str().unwrap()];
        args.extend(["--video", video.to_str().unwrap()]);
        args.extend(extra);
        failure(&args, &[])
    };
    let err = eval(&["--env", "Hopper-v4"]);
    assert!(
        err.contains("Hopper-v4 has obs/action dims (11, 3)"),
        "{err}"
    );
    let err = eval(&["--episodes", "0"]);
    assert!(err.contains("--episodes must be at least 1"), "{err}");
    assert!(!video.exists(), "a refused video left a file");
    std::fs::remove_dir_all(&dir).unwrap();
}
