//! Faces of an NCA state follow the frame's face table exactly (DESIGN section 2), for the
//! whole volume and for corner crops.

use burn::tensor::{Device, Tensor};
use xylem::Volume;
use xylem::frame::Face;
use xylem::nca::faces::face_patches;
use xylem::nca::region::Region;
use xylem::nca::tensors::{tensor_from, to_vec};

/// A `[3, n, n, n]` state whose channels hold the voxel's own indices (i, j, k).
fn index_state(n: usize) -> Tensor<4> {
    let v = n * n * n;
    let mut data = vec![0.0f32; 3 * v];
    for i in 0..n {
        for j in 0..n {
            for k in 0..n {
                let o = (i * n + j) * n + k;
                data[o] = i as f32;
                data[v + o] = j as f32;
                data[2 * v + o] = k as f32;
            }
        }
    }
    tensor_from(data, [3, n, n, n], &Device::flex())
}

/// The voxel (i, j, k) stored at pixel (r, c) of a `[3, h, w]` patch.
fn voxel_at(data: &[f32], h: usize, w: usize, r: usize, c: usize) -> [usize; 3] {
    let p = r * w + c;
    [0, 1, 2].map(|ch| data[ch * h * w + p] as usize)
}

#[test]
fn whole_volume_faces_match_face_pixel_points() {
    let n = 5;
    let state = index_state(n);
    let patches = face_patches(&state, &Region::whole(n), &Face::ALL);
    assert_eq!(patches.len(), 6);
    let volume = Volume::zeros([n, n, n], 1);
    for patch in patches {
        assert_eq!(patch.origin, [0, 0]);
        assert_eq!(patch.image.dims(), [3, n, n]);
        let data = to_vec(patch.image.clone()).unwrap();
        let normal = patch.face.normal();
        for r in 0..n {
            for c in 0..n {
                let [i, j, k] = voxel_at(&data, n, n, r, c);
                let voxel = volume.voxel_point(i, j, k);
                let pixel = patch.face.pixel_point(r, c, n);
                // In the face plane the voxel centre is the pixel centre; along the normal it is
                // the outermost voxel layer, half a voxel inside the face.
                let along = normal.dot(voxel);
                let in_plane = voxel - normal * along;
                let pixel_in_plane = pixel - normal * normal.dot(pixel);
                assert!(
                    (in_plane - pixel_in_plane).length() < 1e-6,
                    "face {} pixel ({r}, {c}) -> voxel ({i}, {j}, {k})",
                    patch.face
                );
                assert!(
                    (along - (0.5 - 0.5 / n as f32)).abs() < 1e-6,
                    "face {}",
                    patch.face
                );
            }
        }
    }
}

#[test]
fn corner_crops_give_the_matching_part_of_each_touched_face() {
    let (n, crop) = (8, 3);
    let state = index_state(n);
    let whole: Vec<(Face, Vec<f32>)> = face_patches(&state, &Region::whole(n), &Face::ALL)
        .into_iter()
        .map(|p| (p.face, to_vec(p.image).unwrap()))
        .collect();
    for corner in 0..8 {
        let region = Region::corner(n, crop, corner);
        let [ox, oy, oz] = region.offset;
        let sub = state
            .clone()
            .narrow(1, ox, crop)
            .narrow(2, oy, crop)
            .narrow(3, oz, crop);
        let patches = face_patches(&sub, &region, &Face::ALL);
        assert_eq!(patches.len(), 3, "a corner crop touches three faces");
        for patch in patches {
            let full = &whole.iter().find(|(f, _)| *f == patch.face).unwrap().1;
            let data = to_vec(patch.image.clone()).unwrap();
            let [r0, c0] = patch.origin;
            for r in 0..crop {
                for c in 0..crop {
                    assert_eq!(
                        voxel_at(&data, crop, crop, r, c),
                        voxel_at(full, n, n, r0 + r, c0 + c),
                        "corner {corner} face {} pixel ({r}, {c})",
                        patch.face
                    );
                }
            }
        }
    }
}

#[test]
fn only_requested_faces_are_returned() {
    let state = index_state(4);
    let patches = face_patches(&state, &Region::whole(4), &[Face::B, Face::E]);
    let faces: Vec<Face> = patches.iter().map(|p| p.face).collect();
    assert_eq!(faces, vec![Face::B, Face::E]);
}
