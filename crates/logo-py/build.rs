//! The wheel's extension finds MuJoCo in the `mujoco` wheel it depends on:
//! site-packages/logo_rl/_logo_rl.abi3.so → site-packages/mujoco/libmujoco.so.3.17.0.
fn main() {
    println!("cargo::rustc-link-arg-cdylib=-Wl,-rpath,$ORIGIN/../mujoco");
}
