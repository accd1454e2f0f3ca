//! NumPy `.npy` files holding one C-order float64 or float32 array, through the `npyz`
//! crate. Anything else is an error that says what was found; the size the header
//! declares is checked against the file before anything is allocated for it.

use std::path::Path;

use npyz::{Order, WriterBuilder};

use crate::DataError;

#[derive(Debug, Clone, PartialEq)]
pub struct NpyArray {
    pub shape: Vec<usize>,
    pub data: Vec<f64>,
}

/// Reads a C-order array of float64 (`<f8`, `>f8`) or float32 (`<f4`, `>f4`, widened).
pub fn read_npy(path: &Path) -> Result<NpyArray, DataError> {
    let bytes = std::fs::read(path).map_err(|source| DataError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let err = |reason: String| DataError::Npy {
        path: path.to_path_buf(),
        reason,
    };
    check_preamble(path, &bytes)?;
    let file = npyz::NpyFile::new(&bytes[..]).map_err(|e| err(e.to_string()))?;
    if file.order() == Order::Fortran {
        return Err(err("Fortran-order arrays are not supported".into()));
    }
    let dtype = file.dtype();
    let descr = dtype.descr();
    let item_size = match &dtype {
        npyz::DType::Plain(t) if t.type_char() == npyz::TypeChar::Float => t.size_field(),
        _ => 0,
    };
    if item_size != 8 && item_size != 4 {
        return Err(err(format!(
            "dtype {descr}, expected float64 ('<f8') or float32 ('<f4')"
        )));
    }
    let shape: Vec<usize> = file
        .shape()
        .iter()
        .map(|&d| usize::try_from(d).map_err(|_| err(format!("dimension {d} is too large"))))
        .collect::<Result<_, _>>()?;
    let needed = file
        .shape()
        .iter()
        .try_fold(item_size, |acc, &d| acc.checked_mul(d))
        .ok_or_else(|| err(format!("shape {shape:?} overflows")))?;
    let header_len = bytes.len() - file.into_inner().len();
    let available = (bytes.len() - header_len) as u64;
    if available != needed {
        return Err(err(format!(
            "shape {shape:?} of {descr} needs {needed} data bytes, the file has {available}"
        )));
    }
    let file = npyz::NpyFile::new(&bytes[..]).map_err(|e| err(e.to_string()))?;
    let data = if item_size == 8 {
        file.into_vec::<f64>()
    } else {
        file.into_vec::<f32>()
            .map(|v| v.into_iter().map(f64::from).collect())
    }
    .map_err(|e| err(e.to_string()))?;
    Ok(NpyArray { shape, data })
}

/// The magic string, the version and the header length the file declares, checked
/// against the file's size before `npyz` reads (and allocates for) the header.
fn check_preamble(path: &Path, bytes: &[u8]) -> Result<(), DataError> {
    const MAGIC: &[u8] = b"\x93NUMPY";
    let err = |reason: String| DataError::Npy {
        path: path.to_path_buf(),
        reason,
    };
    if !bytes.starts_with(MAGIC) {
        return Err(err("not a .npy file (no \\x93NUMPY magic string)".into()));
    }
    let (major, minor) = match bytes.get(6..8) {
        Some(&[major, minor]) => (major, minor),
        _ => {
            return Err(err(format!(
                "{} bytes: no version after the magic string",
                bytes.len()
            )));
        }
    };
    let (length_at, length_bytes) = match major {
        1 => (8, 2),
        2 | 3 => (8, 4),
        _ => {
            return Err(err(format!(
                "format version {major}.{minor}, expected 1.0, 2.0 or 3.0"
            )));
        }
    };
    let field = bytes
        .get(length_at..length_at + length_bytes)
        .ok_or_else(|| {
            err(format!(
                "{} bytes: the header length is cut off",
                bytes.len()
            ))
        })?;
    let header_len = field
        .iter()
        .rev()
        .fold(0u64, |acc, &b| (acc << 8) | u64::from(b));
    let header_end = (length_at + length_bytes) as u64 + header_len;
    if header_end > bytes.len() as u64 {
        return Err(err(format!(
            "the header declares {header_len} bytes, past the end of the {}-byte file",
            bytes.len()
        )));
    }
    Ok(())
}

/// Writes a C-order little-endian float64 array as `.npy`.
pub fn write_npy(path: &Path, shape: &[usize], data: &[f64]) -> Result<(), DataError> {
    assert_eq!(
        shape.iter().product::<usize>(),
        data.len(),
        "shape and data length agree"
    );
    let io = |source| DataError::Io {
        path: path.to_path_buf(),
        source,
    };
    let shape: Vec<u64> = shape.iter().map(|&d| d as u64).collect();
    let file = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
    let mut writer = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&shape)
        .writer(file)
        .begin_nd()
        .map_err(io)?;
    writer.extend(data.iter().copied()).map_err(io)?;
    writer.finish().map_err(io)
}
