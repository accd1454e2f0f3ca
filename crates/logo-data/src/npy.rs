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
