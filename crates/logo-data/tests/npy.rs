use std::path::{Path, PathBuf};

use logo_data::{DataError, Demonstrations, read_npy, write_npy};

fn reference(name: &str) -> Option<PathBuf> {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/reference/logo-demos")
        .join(name);
    if p.exists() {
        Some(p)
    } else {
        eprintln!("skipped: {} is not there", p.display());
        None
    }
}

#[test]
fn the_logo_demonstrations_load_with_their_listed_shapes() {
    for (file, rows, obs, act) in [
        ("hopper.npy", 3869, 11, 3),
        ("halfcheetah.npy", 5000, 17, 6),
        ("walker2d.npy", 4584, 17, 6),
        ("inverted_double_pendulum.npy", 183, 11, 1),
    ] {
        let Some(path) = reference(file) else { return };
        let demos = Demonstrations::from_npy(&path, obs, act).unwrap();
        assert_eq!(demos.len(), rows, "{file}");
        assert!(
            demos.actions.iter().all(|a| a.abs() < 1.0),
            "{file}: actions strictly inside (-1, 1)"
        );
        let err = Demonstrations::from_npy(&path, obs + 1, act)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains(file) && err.contains(&format!("{} columns", obs + act)),
            "{err}"
        );
    }
}

/// A `.npy` image whose dtype string is `descr` (three characters, as `<f8`), for the
/// reader's error paths.
fn npy_bytes(descr: &str, shape: &[usize], data: &[f64]) -> Vec<u8> {
    let path = std::env::temp_dir().join(format!("logo-npy-bytes-{}.npy", std::process::id()));
    write_npy(&path, shape, data).unwrap();
    let mut bytes = std::fs::read(&path).unwrap();
    let at = bytes.windows(3).position(|w| w == b"<f8").unwrap();
    bytes[at..at + 3].copy_from_slice(descr.as_bytes());
    bytes
}

#[test]
fn bad_files_are_errors_naming_the_problem() {
    let dir = std::env::temp_dir().join(format!("logo-npy-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("d.npy");
    let good = npy_bytes("<f8", &[2, 3], &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
    std::fs::write(&path, &good).unwrap();
    assert_eq!(read_npy(&path).unwrap().shape, vec![2, 3]);
    let demos = Demonstrations::from_npy(&path, 2, 1).unwrap();
    assert_eq!(
        (demos.obs, demos.actions),
        (vec![1.0, 2.0, 4.0, 5.0], vec![3.0, 6.0])
    );

    std::fs::write(
        &path,
        npy_bytes("<f8", &[2, 3], &[1.0, 2.0, f64::NAN, 4.0, 5.0, 6.0]),
    )
    .unwrap();
    let err = Demonstrations::from_npy(&path, 2, 1).unwrap_err();
    assert!(
        matches!(
            err,
            DataError::NonFinite {
                row: 0,
                column: 2,
                field: "action",
                ..
            }
        ),
        "{err}"
    );
    // Integers are refused, naming the dtype found.
    std::fs::write(&path, npy_bytes("<i8", &[2, 3], &[0.0; 6])).unwrap();
    let err = read_npy(&path).unwrap_err().to_string();
    assert!(err.contains("<i8") && err.contains("d.npy"), "{err}");
    // A float32 header over float64-sized data: the sizes disagree.
    std::fs::write(&path, npy_bytes("<f4", &[2, 3], &[0.0; 6])).unwrap();
    let err = read_npy(&path).unwrap_err().to_string();
    assert!(
        err.contains("needs 24 data bytes, the file has 48"),
        "{err}"
    );
    // A shape whose size overflows is an error before anything is allocated.
    let dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (4611686018427387904, 8), }";
    let mut huge = b"\x93NUMPY\x01\x00".to_vec();
    huge.extend((dict.len() as u16 + 1).to_le_bytes());
    huge.extend(dict.as_bytes());
    huge.push(b'\n');
    huge.extend([0u8; 64]);
    std::fs::write(&path, &huge).unwrap();
    let err = read_npy(&path).unwrap_err().to_string();
    assert!(err.contains("overflows"), "{err}");
    // A header length past the end of the file is an error before anything is allocated
    // for it (a version-2 preamble declaring 4 GiB used to abort the process).
    let mut long = b"\x93NUMPY\x02\x00".to_vec();
    long.extend(0xFFFF_FFF0u32.to_le_bytes());
    long.extend(b"{'descr': '<f8'");
    std::fs::write(&path, &long).unwrap();
    let err = read_npy(&path).unwrap_err().to_string();
    assert!(
        err.contains("d.npy") && err.contains("declares 4294967280 bytes, past the end"),
        "{err}"
    );
    // Every truncation is an error, never a panic.
    for n in 0..good.len() {
        std::fs::write(&path, &good[..n]).unwrap();
        assert!(read_npy(&path).is_err(), "truncated to {n} bytes");
    }
}

/// float32 arrays (as NumPy writes them by default from float32 data) load widened.
#[test]
fn float32_arrays_load_as_float64() {
    use npyz::WriterBuilder;
    let path = std::env::temp_dir().join(format!("logo-npy-f32-{}.npy", std::process::id()));
    let values: Vec<f32> = vec![0.5, -1.25, 3.0, 1e-3, 7.5, -2.0];
    let mut writer = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&[3, 2])
        .writer(std::fs::File::create(&path).unwrap())
        .begin_nd()
        .unwrap();
    writer.extend(values.iter().copied()).unwrap();
    writer.finish().unwrap();
    let array = read_npy(&path).unwrap();
    assert_eq!(array.shape, vec![3, 2]);
    let want: Vec<f64> = values.iter().map(|&v| f64::from(v)).collect();
    assert_eq!(array.data, want);
}
