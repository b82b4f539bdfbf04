//! Filling the texels around the layout's islands from the nearest covered
//! texel, so that filtering and mip-mapping never read empty texels.

use crate::texels::EMPTY;
use std::collections::VecDeque;

/// For every empty texel within `margin` texels (8-connected steps) of a
/// covered one: (that texel, the covered texel it copies), both as
/// y·N + x, found breadth-first so each copies from a nearest covered
/// texel. `index` is [`crate::TexelSurfels::index`].
pub fn dilation_offsets(index: &[u32], resolution: u32, margin: u32) -> Vec<(u32, u32)> {
    let n = resolution as i64;
    let mut source = vec![EMPTY; index.len()];
    let mut queue = VecDeque::new();
    for (texel, &surfel) in index.iter().enumerate() {
        if surfel != EMPTY {
            source[texel] = texel as u32;
            queue.push_back((texel as u32, 0u32));
        }
    }
    let mut offsets = Vec::new();
    while let Some((texel, steps)) = queue.pop_front() {
        if steps == margin {
            continue;
        }
        let (x, y) = (texel as i64 % n, texel as i64 / n);
        for (dx, dy) in [
            (-1, 0),
            (1, 0),
            (0, -1),
            (0, 1),
            (-1, -1),
            (1, -1),
            (-1, 1),
            (1, 1),
        ] {
            let (nx, ny) = (x + dx, y + dy);
            if nx < 0 || ny < 0 || nx >= n || ny >= n {
                continue;
            }
            let neighbour = (ny * n + nx) as usize;
            if source[neighbour] == EMPTY {
                source[neighbour] = source[texel as usize];
                offsets.push((neighbour as u32, source[texel as usize]));
                queue.push_back((neighbour as u32, steps + 1));
            }
        }
    }
    offsets
}
