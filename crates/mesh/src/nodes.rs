//! Node positions stored as a structure of arrays.

use nalgebra::Vector3;

/// Reference positions of the mesh nodes [m], one entry per node in each array.
///
/// Structure of arrays: element kernels gather the coordinates of thousands of elements
/// per batch through their connectivity, and solvers update one coordinate component at a
/// time. A node's id is its index. The three arrays must have the same length, which
/// [`Nodes::push`] keeps and [`super::Mesh::validate`] checks (the fields are public so
/// that importers and solvers can work on the arrays directly).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Nodes {
    /// x coordinate of each node [m].
    pub x: Vec<f64>,
    /// y coordinate of each node [m].
    pub y: Vec<f64>,
    /// z coordinate of each node [m].
    pub z: Vec<f64>,
}

impl Nodes {
    /// No nodes.
    pub fn new() -> Self {
        Self::default()
    }

    /// No nodes, room for `capacity` of them.
    pub fn with_capacity(capacity: usize) -> Self {
        Self {
            x: Vec::with_capacity(capacity),
            y: Vec::with_capacity(capacity),
            z: Vec::with_capacity(capacity),
        }
    }

    /// Number of nodes (the length of `x`).
    pub fn len(&self) -> usize {
        self.x.len()
    }

    /// True when there are no nodes.
    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Appends a node at `position` [m] and returns its id.
    ///
    /// # Panics
    /// If the mesh already holds 2³² nodes (ids are `u32`).
    pub fn push(&mut self, position: Vector3<f64>) -> u32 {
        let id = u32::try_from(self.x.len()).expect("node ids are u32: at most 2^32 nodes");
        self.x.push(position.x);
        self.y.push(position.y);
        self.z.push(position.z);
        id
    }

    /// Position of node `i` [m].
    ///
    /// # Panics
    /// If `i` is out of range.
    #[inline]
    pub fn position(&self, i: usize) -> Vector3<f64> {
        Vector3::new(self.x[i], self.y[i], self.z[i])
    }

    /// Moves node `i` to `position` [m].
    ///
    /// # Panics
    /// If `i` is out of range.
    #[inline]
    pub fn set_position(&mut self, i: usize, position: Vector3<f64>) {
        self.x[i] = position.x;
        self.y[i] = position.y;
        self.z[i] = position.z;
    }

    /// Writes the positions [m] of the nodes `ids` into `out[..ids.len()]`: the gather of an
    /// element's coordinates through its connectivity.
    ///
    /// # Panics
    /// If an id is out of range or `out` is shorter than `ids`.
    #[inline]
    pub fn gather(&self, ids: &[u32], out: &mut [Vector3<f64>]) {
        for (o, &id) in out[..ids.len()].iter_mut().zip(ids) {
            *o = self.position(id as usize);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn push_position_and_gather() {
        let mut nodes = Nodes::new();
        assert!(nodes.is_empty());
        assert_eq!(nodes.push(Vector3::new(1.0, 2.0, 3.0)), 0);
        assert_eq!(nodes.push(Vector3::new(-4.0, 5.0, 6.5)), 1);
        assert_eq!(nodes.len(), 2);
        assert_eq!(nodes.position(1), Vector3::new(-4.0, 5.0, 6.5));
        let mut out = [Vector3::zeros(); 3];
        nodes.gather(&[1, 0], &mut out);
        assert_eq!(out[0], Vector3::new(-4.0, 5.0, 6.5));
        assert_eq!(out[1], Vector3::new(1.0, 2.0, 3.0));
        assert_eq!(out[2], Vector3::zeros());
        nodes.set_position(0, Vector3::new(0.5, 0.0, 0.0));
        assert_eq!(nodes.x, vec![0.5, -4.0]);
        assert_eq!(nodes.z, vec![0.0, 6.5]);
    }
}
