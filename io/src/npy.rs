//! NumPy `.npy` point files: a 2-D float64 or float32 array read (its header checked
//! before any parser sees it), float64 in C order written.

use super::{format_error, IoError};
use crate::PointSet;

pub(super) const NPY_MAGIC: &[u8] = b"\x93NUMPY";

/// Checks a `.npy` header before any other code parses it: the version, a length the
/// format allows, printable ASCII, and one flat dictionary with exactly the keys
/// `descr`, `fortran_order` and `shape` (the header grammar is a Python literal; a
/// general parser of it can take exponential time on nested braces).
fn check_npy_header(bytes: &[u8], file: &str) -> Result<(), IoError> {
    let bad = |why: &str| {
        format_error(
            file,
            format!(
                "not a valid .npy file ({why}); expected a NumPy .npy file of a 2-D float64 \
                 or float32 array"
            ),
        )
    };
    let major = *bytes.get(6).ok_or_else(|| bad("too short"))?;
    let (len, start) = match major {
        1 => (
            u16::from_le_bytes([
                *bytes.get(8).ok_or_else(|| bad("too short"))?,
                *bytes.get(9).ok_or_else(|| bad("too short"))?,
            ]) as usize,
            10,
        ),
        2 | 3 => {
            let b = bytes.get(8..12).ok_or_else(|| bad("too short"))?;
            (u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize, 12)
        }
        v => return Err(bad(&format!("format version {v}, expected 1, 2 or 3"))),
    };
    if len > 1 << 16 {
        return Err(bad(&format!(
            "a header of {len} bytes, at most 65536 accepted"
        )));
    }
    let header = bytes
        .get(start..start + len)
        .ok_or_else(|| bad("the header is cut short"))?;
    if !header
        .iter()
        .all(|&b| (0x20..0x7f).contains(&b) || b == b'\n')
    {
        return Err(bad("the header is not printable ASCII"));
    }
    let text = std::str::from_utf8(header).map_err(|_| bad("the header is not ASCII"))?;
    let body = text.trim_end_matches([' ', '\n']);
    let opens = body.matches('{').count();
    let closes = body.matches('}').count();
    if !(body.starts_with('{') && body.ends_with('}') && opens == 1 && closes == 1) {
        return Err(bad("the header is not one flat dictionary"));
    }
    for key in ["descr", "fortran_order", "shape"] {
        if !(body.contains(&format!("'{key}'")) || body.contains(&format!("\"{key}\""))) {
            return Err(bad(&format!("the header has no '{key}'")));
        }
    }
    if body.matches(':').count() != 3 {
        return Err(bad(
            "the header has keys other than 'descr', 'fortran_order' and 'shape'",
        ));
    }
    Ok(())
}

pub(super) fn parse_npy(bytes: &[u8], file: &str) -> Result<PointSet, IoError> {
    const EXPECTED: &str = "expected a 2-D array of float64 or float32";
    check_npy_header(bytes, file)?;
    let mut rest = bytes;
    let header = npyz::NpyHeader::from_reader(&mut rest)
        .map_err(|e| format_error(file, format!("not a valid .npy file ({e})")))?;
    let shape = header.shape().to_vec();
    let (n, s) = match shape[..] {
        [n] => (n, 1),
        [n, s] => (n, s),
        _ => {
            return Err(format_error(
                file,
                format!("{EXPECTED} (got shape {shape:?})"),
            ))
        }
    };
    if n == 0 {
        return Err(IoError::Empty {
            file: file.to_string(),
        });
    }
    if s == 0 {
        return Err(format_error(
            file,
            format!("{EXPECTED} (got shape {shape:?})"),
        ));
    }
    let dtype = header.dtype();
    let width = match &dtype {
        npyz::DType::Plain(t) if t.type_char() == npyz::TypeChar::Float => match t.size_field() {
            8 => 8u64,
            4 => 4u64,
            _ => 0,
        },
        _ => 0,
    };
    if width == 0 {
        return Err(format_error(
            file,
            format!("{EXPECTED} (got dtype {})", dtype.descr()),
        ));
    }
    // Checked before decoding so that a corrupt header cannot ask for a huge allocation.
    let needed = n.checked_mul(s).and_then(|len| len.checked_mul(width));
    if needed.is_none_or(|b| b > rest.len() as u64) {
        return Err(format_error(
            file,
            format!(
                "truncated: shape {shape:?} needs {} bytes of data, the file has {}",
                needed.map_or_else(|| "more than 2^64".to_string(), |b| b.to_string()),
                rest.len()
            ),
        ));
    }
    // Bytes past the array are no part of the format (np.save writes none; its padding
    // is inside the header): they mean a header whose shape is not the data's, or two
    // files joined, and reading on would keep a set that is not the one written.
    if let Some(needed) = needed.filter(|&b| b < rest.len() as u64) {
        let found = rest.len() as u64;
        let ty = if width == 8 { "float64" } else { "float32" };
        return Err(format_error(
            file,
            format!(
                "{} bytes after the array: the array's data must end the file (expected \
                 {needed} bytes of data for shape {shape:?} of {ty}, found {found})",
                found - needed
            ),
        ));
    }
    let (n, s) = (n as usize, s as usize);
    let fortran = header.order() == npyz::Order::Fortran;
    let npy = npyz::NpyFile::with_header(header, rest);
    let decoded = if width == 8 {
        npy.into_vec::<f64>()
    } else {
        npy.into_vec::<f32>()
            .map(|v| v.into_iter().map(f64::from).collect())
    };
    let flat = decoded.map_err(|e| format_error(file, format!("corrupt .npy data ({e})")))?;
    let data = if fortran && s > 1 {
        // Column-major on disk: element (i, k) sits at k·n + i.
        let mut data = vec![0.0; n * s];
        for (k, column) in flat.chunks_exact(n).enumerate() {
            for (i, &v) in column.iter().enumerate() {
                data[i * s + k] = v;
            }
        }
        data
    } else {
        flat
    };
    PointSet::new(n, s, data).map_err(|error| IoError::Points {
        file: file.to_string(),
        error,
    })
}

pub(super) fn to_npy(points: &PointSet) -> Vec<u8> {
    let mut out = Vec::with_capacity(128 + 8 * points.coordinate_count());
    write_npy(&mut out, points).expect("writing to memory");
    out
}

/// The bytes of [`to_npy`] written to `w` as they are made: a copy of the points in
/// memory would double a large run's peak.
pub(super) fn write_npy(w: &mut dyn std::io::Write, points: &PointSet) -> std::io::Result<()> {
    // Format version 1.0: magic, version, u16 header length, a Python dict literal padded
    // with spaces and ended by a newline so that the data starts 64-byte aligned.
    let mut header = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}",
        points.n(),
        points.s()
    );
    let unpadded = NPY_MAGIC.len() + 2 + 2 + header.len() + 1;
    header.extend(std::iter::repeat_n(
        ' ',
        unpadded.next_multiple_of(64) - unpadded,
    ));
    header.push('\n');
    w.write_all(NPY_MAGIC)?;
    w.write_all(&[1, 0])?;
    // A dict for two dimensions is far below the 65 535-byte limit of version 1.0.
    w.write_all(&(header.len() as u16).to_le_bytes())?;
    w.write_all(header.as_bytes())?;
    let mut block = Vec::with_capacity(8 << 12);
    for part in points.as_slice().chunks(1 << 12) {
        block.clear();
        for &v in part {
            block.extend_from_slice(&v.to_le_bytes());
        }
        w.write_all(&block)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `data` as `np.save` writes an array of `descr` and `shape` (a Python tuple): format
    /// 1.0, the dictionary padded with spaces and a newline so that the data starts at a
    /// multiple of 64 bytes.
    fn np_saved(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
        let order = if fortran { "True" } else { "False" };
        let mut header =
            format!("{{'descr': '{descr}', 'fortran_order': {order}, 'shape': {shape}, }}");
        let unpadded = NPY_MAGIC.len() + 4 + header.len() + 1;
        header.extend(std::iter::repeat_n(
            ' ',
            unpadded.next_multiple_of(64) - unpadded,
        ));
        header.push('\n');
        let mut out = NPY_MAGIC.to_vec();
        out.extend_from_slice(&[1, 0]);
        out.extend_from_slice(&(header.len() as u16).to_le_bytes());
        out.extend_from_slice(header.as_bytes());
        out.extend_from_slice(data);
        out
    }

    fn f64_bytes(values: &[f64]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    fn f32_bytes(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    fn refusal(bytes: &[u8]) -> String {
        parse_npy(bytes, "p.npy").unwrap_err().to_string()
    }

    /// Every layout np.save gives a point set reads, its header's padding not taken for
    /// data past the array.
    #[test]
    fn files_as_np_save_writes_them_read() {
        let c = np_saved(
            "<f8",
            false,
            "(2, 2)",
            &f64_bytes(&[0.25, 0.5, 0.75, 0.125]),
        );
        // The first bytes and length np.save (NumPy 2.4) gives this array.
        assert_eq!(&c[..10], b"\x93NUMPY\x01\x00v\x00");
        assert_eq!(c.len(), 160);
        let p = parse_npy(&c, "c.npy").unwrap();
        assert_eq!(p.as_slice(), &[0.25, 0.5, 0.75, 0.125]);
        let f32 = np_saved(
            "<f4",
            false,
            "(2, 2)",
            &f32_bytes(&[0.25, 0.5, 0.75, 0.125]),
        );
        assert_eq!(parse_npy(&f32, "f.npy").unwrap().as_slice(), p.as_slice());
        // Column-major: (0.25, 0.75) is the first column.
        let fortran = np_saved("<f8", true, "(2, 2)", &f64_bytes(&[0.25, 0.75, 0.5, 0.125]));
        assert_eq!(
            parse_npy(&fortran, "F.npy").unwrap().as_slice(),
            p.as_slice()
        );
        let column = np_saved("<f8", false, "(2,)", &f64_bytes(&[0.5, 0.25]));
        let p = parse_npy(&column, "1.npy").unwrap();
        assert_eq!((p.n(), p.s()), (2, 1));
        let written = to_npy(&PointSet::from_rows(&[[0.25, 0.5], [0.75, 0.125]]).unwrap());
        assert_eq!(written, c);
    }

    /// Bytes after the array's data, from one to a whole second array, are refused with
    /// the file's name, the data's length expected and the length found.
    #[test]
    fn bytes_after_the_array_are_refused() {
        let data = f64_bytes(&[0.25, 0.5, 0.75, 0.125]);
        let good = np_saved("<f8", false, "(2, 2)", &data);
        for extra in [vec![0u8], b"\n".to_vec(), vec![0u8; 8], good.clone()] {
            let mut bytes = good.clone();
            bytes.extend_from_slice(&extra);
            let e = refusal(&bytes);
            assert!(e.starts_with("p.npy: "), "{e}");
            assert!(e.contains("the array's data must end the file"), "{e}");
            assert!(
                e.contains(&format!(
                    "expected 32 bytes of data for shape [2, 2] of float64, found {}",
                    32 + extra.len()
                )),
                "{e}"
            );
        }
        let mut f32 = np_saved("<f4", true, "(2, 2)", &data[..16]);
        f32.extend_from_slice(&[0u8; 4]);
        assert!(refusal(&f32)
            .contains("expected 16 bytes of data for shape [2, 2] of float32, found 20"));
        // A file cut short is still refused as truncated.
        let e = refusal(&good[..good.len() - 1]);
        assert!(
            e.contains("truncated: shape [2, 2] needs 32 bytes of data, the file has 31"),
            "{e}"
        );
    }
}
