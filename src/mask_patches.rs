//! The 8-connected patches of a binary mask: ring contours in the ring images
//! (`fit::contours`), vessels among a photo's dark pixels (`metrics::vessels`).

/// The patch of `mask` (row-major, `width` pixels a row) that holds `start`, as pixel
/// indices in the order found; marks them in `seen`, so each patch is found once.
pub(crate) fn patch_at(mask: &[bool], seen: &mut [bool], start: usize, width: usize) -> Vec<usize> {
    let height = mask.len() / width.max(1);
    let mut pixels = Vec::new();
    let mut stack = vec![start];
    seen[start] = true;
    while let Some(i) = stack.pop() {
        pixels.push(i);
        let (r, c) = ((i / width) as isize, (i % width) as isize);
        for dr in -1..=1 {
            for dc in -1..=1 {
                let (rr, cc) = (r + dr, c + dc);
                if rr < 0 || cc < 0 || rr >= height as isize || cc >= width as isize {
                    continue;
                }
                let j = rr as usize * width + cc as usize;
                if mask[j] && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
    }
    pixels
}

/// The pixel counts of all patches of `mask`, in the order of their first pixels.
pub(crate) fn patch_sizes(mask: &[bool], width: usize) -> Vec<usize> {
    let mut seen = vec![false; mask.len()];
    let mut sizes = Vec::new();
    for i in 0..mask.len() {
        if mask[i] && !seen[i] {
            sizes.push(patch_at(mask, &mut seen, i, width).len());
        }
    }
    sizes
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn patches_join_diagonals_and_are_counted_once() {
        // A 2-pixel diagonal patch, a lone pixel and a 5-pixel row, on a 6 x 4 grid.
        let rows = ["x.....", ".x..x.", "......", "xxxxx."];
        let mask: Vec<bool> = rows
            .iter()
            .flat_map(|r| r.chars().map(|c| c == 'x'))
            .collect();
        assert_eq!(patch_sizes(&mask, 6), [2, 1, 5]);
    }
}
