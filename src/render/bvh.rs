//! A bounding volume hierarchy over triangles (median split on the longest axis), flattened
//! into an array, with Moller-Trumbore triangle tests.

use glam::Vec3;

use super::camera::Ray;
use super::mesh::TriMesh;

#[derive(Clone, Copy, Debug)]
struct Node {
    lo: Vec3,
    hi: Vec3,
    /// Leaf: first triangle in `order`; inner: index of the right child (left is next).
    start: u32,
    /// Leaf: triangle count; inner: 0.
    count: u32,
}

pub(crate) struct Bvh {
    nodes: Vec<Node>,
    /// Triangle indices in leaf order.
    order: Vec<u32>,
}

const LEAF_SIZE: usize = 4;

impl Bvh {
    pub(crate) fn build(mesh: &TriMesh) -> Self {
        let centroids: Vec<Vec3> = (0..mesh.triangles.len())
            .map(|i| {
                let [a, b, c] = mesh.triangle(i);
                (a + b + c) / 3.0
            })
            .collect();
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * mesh.triangles.len() / LEAF_SIZE + 1),
            order: (0..mesh.triangles.len() as u32).collect(),
        };
        let n = bvh.order.len();
        bvh.build_node(mesh, &centroids, 0, n);
        bvh
    }

    fn bounds(&self, mesh: &TriMesh, start: usize, end: usize) -> (Vec3, Vec3) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for &t in &self.order[start..end] {
            for p in mesh.triangle(t as usize) {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        (lo, hi)
    }

    fn build_node(
        &mut self,
        mesh: &TriMesh,
        centroids: &[Vec3],
        start: usize,
        end: usize,
    ) -> usize {
        let (lo, hi) = self.bounds(mesh, start, end);
        let index = self.nodes.len();
        self.nodes.push(Node {
            lo,
            hi,
            start: start as u32,
            count: (end - start) as u32,
        });
        if end - start <= LEAF_SIZE {
            return index;
        }
        let axis = (hi - lo)
            .to_array()
            .iter()
            .enumerate()
            .fold(
                0,
                |best, (i, &e)| if e > (hi - lo)[best] { i } else { best },
            );
        let mid = (start + end) / 2;
        self.order[start..end].select_nth_unstable_by(mid - start, |a, b| {
            centroids[*a as usize][axis].total_cmp(&centroids[*b as usize][axis])
        });
        self.build_node(mesh, centroids, start, mid);
        let right = self.build_node(mesh, centroids, mid, end);
        self.nodes[index].start = right as u32;
        self.nodes[index].count = 0;
        index
    }

    /// Nearest triangle hit: (triangle, t, barycentric u, v).
    pub(crate) fn intersect(
        &self,
        mesh: &TriMesh,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
    ) -> Option<(usize, f32, f32, f32)> {
        let inv = ray.dir.recip();
        let mut best: Option<(usize, f32, f32, f32)> = None;
        let mut limit = t_max;
        let mut stack = [0usize; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let index = stack[top];
            let node = self.nodes[index];
            if !slab_hit(node.lo, node.hi, ray.origin, inv, t_min, limit) {
                continue;
            }
            if node.count > 0 {
                for &t in &self.order[node.start as usize..(node.start + node.count) as usize] {
                    if let Some((d, u, v)) =
                        triangle_hit(mesh.triangle(t as usize), ray, t_min, limit)
                    {
                        limit = d;
                        best = Some((t as usize, d, u, v));
                    }
                }
            } else {
                // The left child is stored right after its parent, the right one at `start`.
                // Depth is ~log2(triangles / 4), far below the stack size.
                stack[top] = index + 1;
                stack[top + 1] = node.start as usize;
                top += 2;
            }
        }
        best
    }
}

/// Ray / axis-aligned box overlap within (t_min, t_max).
fn slab_hit(lo: Vec3, hi: Vec3, origin: Vec3, inv: Vec3, t_min: f32, t_max: f32) -> bool {
    let t0 = (lo - origin) * inv;
    let t1 = (hi - origin) * inv;
    let near = t0.min(t1).max_element().max(t_min);
    let far = t0.max(t1).min_element().min(t_max);
    near <= far
}

/// Moller-Trumbore: (t, u, v) of the hit within (t_min, t_max).
fn triangle_hit(
    [a, b, c]: [Vec3; 3],
    ray: &Ray,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, f32, f32)> {
    let e1 = b - a;
    let e2 = c - a;
    let p = ray.dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-12 {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = ray.origin - a;
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = ray.dir.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    (t > t_min && t < t_max).then_some((t, u, v))
}
