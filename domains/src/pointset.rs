//! The one point-set type of the workspace: n points × s coordinates, row per point,
//! in one contiguous buffer.

use crate::{Error, Result};
use std::sync::Arc;

/// n points in s dimensions, stored row per point (`data[i * s + k]` is coordinate k of
/// point i). Always n ≥ 1, s ≥ 1 and every coordinate finite; a deserialised set is
/// checked by [`PointSet::new`] like any other, so a damaged checkpoint cannot make an
/// invalid one.
///
/// A clone shares the buffer until either copy is changed (then that copy takes a
/// buffer of its own): a run's report, its result and what a caller receives are often
/// the same points, and at 10⁶ × 50 each copy would be 400 MB.
#[derive(Clone, Debug, serde::Deserialize)]
#[serde(try_from = "RawPointSet")]
pub struct PointSet {
    n: usize,
    s: usize,
    data: Arc<Vec<f64>>,
}

impl PartialEq for PointSet {
    fn eq(&self, other: &Self) -> bool {
        // Every coordinate is finite, so a shared buffer is an equal one.
        self.n == other.n
            && self.s == other.s
            && (Arc::ptr_eq(&self.data, &other.data) || self.data == other.data)
    }
}

/// The same fields and form as the buffer written out by a derived implementation.
impl serde::Serialize for PointSet {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut st = serializer.serialize_struct("PointSet", 3)?;
        st.serialize_field("n", &self.n)?;
        st.serialize_field("s", &self.s)?;
        st.serialize_field("data", self.data.as_slice())?;
        st.end()
    }
}

/// The serialised form of a [`PointSet`], validated on the way in.
#[derive(serde::Deserialize)]
struct RawPointSet {
    n: usize,
    s: usize,
    data: Vec<f64>,
}

impl TryFrom<RawPointSet> for PointSet {
    type Error = Error;
    fn try_from(raw: RawPointSet) -> Result<Self> {
        PointSet::new(raw.n, raw.s, raw.data)
    }
}

impl PointSet {
    /// Wraps a row-major buffer, refusing n = 0, s = 0, a length other than n·s, or a
    /// coordinate that is NaN or infinite.
    pub fn new(n: usize, s: usize, data: Vec<f64>) -> Result<Self> {
        if n == 0 {
            return Err(Error::invalid("n", n, "at least 1 point"));
        }
        if s == 0 {
            return Err(Error::invalid("s", s, "at least 1 dimension"));
        }
        if data.len() != n * s {
            return Err(Error::invalid(
                "data length",
                data.len(),
                format!("n·s = {}·{} = {}", n, s, n * s),
            ));
        }
        if let Some(idx) = data.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid(
                format!("point {}, coordinate {}", idx / s + 1, idx % s + 1),
                data[idx],
                "a finite number",
            ));
        }
        Ok(PointSet {
            n,
            s,
            data: Arc::new(data),
        })
    }

    /// Builds a set from rows, refusing ragged rows.
    pub fn from_rows<R: AsRef<[f64]>>(rows: &[R]) -> Result<Self> {
        let n = rows.len();
        let s = rows.first().map(|r| r.as_ref().len()).unwrap_or(0);
        let mut data = Vec::with_capacity(n * s);
        for (i, r) in rows.iter().enumerate() {
            let r = r.as_ref();
            if r.len() != s {
                return Err(Error::invalid(
                    format!("row {}", i + 1),
                    format!("{} coordinates", r.len()),
                    format!("{s} coordinates like row 1"),
                ));
            }
            data.extend_from_slice(r);
        }
        PointSet::new(n, s, data)
    }

    /// Number of points n.
    pub fn n(&self) -> usize {
        self.n
    }

    /// Dimension s.
    pub fn s(&self) -> usize {
        self.s
    }

    /// n·s, the number of coordinates: the length of the flat buffer (and of a gradient).
    /// The number of points is [`PointSet::n`].
    pub fn coordinate_count(&self) -> usize {
        self.data.len()
    }

    /// The flat row-major buffer.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// The flat row-major buffer, mutable. Callers keep the coordinates finite.
    pub fn as_mut_slice(&mut self) -> &mut [f64] {
        Arc::make_mut(&mut self.data).as_mut_slice()
    }

    /// Point i.
    pub fn point(&self, i: usize) -> &[f64] {
        &self.data[i * self.s..(i + 1) * self.s]
    }

    /// Point i, mutable.
    pub fn point_mut(&mut self, i: usize) -> &mut [f64] {
        let s = self.s;
        &mut Arc::make_mut(&mut self.data)[i * s..(i + 1) * s]
    }

    /// The points in order.
    pub fn rows(&self) -> std::slice::ChunksExact<'_, f64> {
        self.data.chunks_exact(self.s)
    }

    /// The flat buffer, consuming the set.
    pub fn into_vec(self) -> Vec<f64> {
        Arc::try_unwrap(self.data).unwrap_or_else(|shared| shared.as_ref().clone())
    }

    /// Coordinate-wise mean of the points.
    pub fn mean(&self) -> Vec<f64> {
        let mut m = vec![0.0; self.s];
        for row in self.rows() {
            for (a, &v) in m.iter_mut().zip(row) {
                *a += v;
            }
        }
        m.iter_mut().for_each(|a| *a /= self.n as f64);
        m
    }

    /// Refuses a set with a coordinate outside [0, 1], naming the first offender.
    pub fn check_unit_cube(&self) -> Result<()> {
        if let Some(idx) = self.data.iter().position(|v| !(0.0..=1.0).contains(v)) {
            return Err(Error::invalid(
                format!(
                    "point {}, coordinate {}",
                    idx / self.s + 1,
                    idx % self.s + 1
                ),
                self.data[idx],
                "a coordinate in [0, 1]",
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_bad_shapes_and_values() {
        assert!(matches!(
            PointSet::new(0, 2, vec![]),
            Err(Error::InvalidArgument { ref name, .. }) if name == "n"
        ));
        assert!(matches!(
            PointSet::new(1, 0, vec![]),
            Err(Error::InvalidArgument { ref name, .. }) if name == "s"
        ));
        assert!(PointSet::new(2, 2, vec![0.1; 3]).is_err());
        let e = PointSet::new(2, 2, vec![0.1, 0.2, f64::NAN, 0.3]).unwrap_err();
        assert!(e.to_string().contains("point 2, coordinate 1"), "{e}");
        let e = PointSet::from_rows(&[vec![0.1, 0.2], vec![0.3]]).unwrap_err();
        assert!(e.to_string().contains("row 2"), "{e}");
    }

    #[test]
    fn a_changed_clone_leaves_the_original_and_serialises_as_before() {
        let p = PointSet::from_rows(&[[0.25, 0.5], [0.75, 0.125]]).unwrap();
        let mut q = p.clone();
        assert_eq!(p, q);
        q.point_mut(1)[0] = 0.5;
        q.as_mut_slice()[0] = 0.0;
        assert_eq!(p.as_slice(), &[0.25, 0.5, 0.75, 0.125]);
        assert_eq!(q.as_slice(), &[0.0, 0.5, 0.5, 0.125]);
        assert_ne!(p, q);
        assert_eq!(p.clone().into_vec(), vec![0.25, 0.5, 0.75, 0.125]);
        // The derived form of { n, s, data: Vec<f64> }.
        let text = serde_json::to_string(&p).unwrap();
        assert_eq!(text, r#"{"n":2,"s":2,"data":[0.25,0.5,0.75,0.125]}"#);
        let back: PointSet = serde_json::from_str(&text).unwrap();
        assert_eq!(back, p);
    }

    #[test]
    fn rows_and_mean() {
        let p = PointSet::from_rows(&[[0.0, 1.0], [0.5, 0.0]]).unwrap();
        assert_eq!(p.point(1), &[0.5, 0.0]);
        assert_eq!(p.mean(), vec![0.25, 0.5]);
        assert!(p.check_unit_cube().is_ok());
        let q = PointSet::from_rows(&[[0.0, 1.5]]).unwrap();
        assert!(q
            .check_unit_cube()
            .unwrap_err()
            .to_string()
            .contains("coordinate 2"));
    }
}
