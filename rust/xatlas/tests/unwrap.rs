//! Unwrapping small meshes through the bridge, and the checks before it.

use sssbake_xatlas::{Atlas, Error, Options, unwrap};

/// A 2 × 2 grid of unit squares in the xy plane: 9 vertices, 8 triangles.
fn grid() -> (Vec<f32>, Vec<u32>) {
    let mut positions = Vec::new();
    for y in 0..3 {
        for x in 0..3 {
            positions.extend([x as f32, y as f32, 0.0]);
        }
    }
    let mut indices = Vec::new();
    for y in 0..2 {
        for x in 0..2 {
            let a = y * 3 + x;
            indices.extend([a, a + 1, a + 4, a, a + 4, a + 3]);
        }
    }
    (positions, indices)
}

/// A closed cube of side 2 with 8 shared corners and 12 triangles, so xatlas
/// must cut seams.
fn cube() -> (Vec<f32>, Vec<u32>) {
    let mut positions = Vec::new();
    for i in 0..8 {
        positions.extend([
            (i & 1) as f32 * 2.0,
            (i >> 1 & 1) as f32 * 2.0,
            (i >> 2) as f32 * 2.0,
        ]);
    }
    let quads = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ];
    let indices = quads
        .iter()
        .flat_map(|q| [q[0], q[1], q[2], q[0], q[2], q[3]])
        .collect();
    (positions, indices)
}

/// Checks what holds for every unwrap: UVs inside the atlas, the input's
/// triangles kept in order through `xref`, every vertex in the single atlas.
fn check(name: &str, positions: &[f32], indices: &[u32], atlas: &Atlas) {
    assert!(atlas.width > 0 && atlas.height > 0, "{name}: {atlas:?}");
    assert!(atlas.atlas_count <= 1, "{name}: {atlas:?}");
    assert!(atlas.texels_per_unit > 0.0, "{name}: {atlas:?}");
    assert_eq!(atlas.indices.len(), indices.len(), "{name}");
    for (k, (&out, &input)) in atlas.indices.iter().zip(indices).enumerate() {
        let vertex = atlas.vertices[out as usize];
        assert_eq!(vertex.xref, input, "{name}: corner {k} moved");
    }
    for vertex in &atlas.vertices {
        assert!((vertex.xref as usize) < positions.len() / 3, "{name}");
        assert_eq!(vertex.atlas_index, Some(0), "{name}");
        let u = vertex.uv[0] / atlas.width as f32;
        let v = vertex.uv[1] / atlas.height as f32;
        assert!(
            (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v),
            "{name}: uv ({u}, {v}) outside [0, 1]"
        );
    }
    // Every vertex is used; seams only split vertices.
    let mut used = vec![false; atlas.vertices.len()];
    for &i in &atlas.indices {
        used[i as usize] = true;
    }
    assert!(used.iter().all(|&u| u), "{name}: unused output vertices");
}

/// A given scale of 10 texels per unit, with no map size: the atlas grows
/// to hold the charts.
const TEN_PER_UNIT: Options = Options {
    resolution: 0,
    padding: 1,
    texels_per_unit: Some(10.0),
};

/// Twice the signed area of a triangle in the atlas, in texels².
fn uv_area2(atlas: &Atlas, t: &[u32]) -> f32 {
    let [a, b, c] = [0, 1, 2].map(|k| atlas.vertices[t[k] as usize].uv);
    (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
}

#[test]
fn a_grid_and_a_cube_unwrap_into_the_unit_square() {
    // xatlas's own estimate of the scale aims at 75% of the map and can
    // overflow into a second atlas; at 30 texels per unit both meshes fit one.
    let options = Options {
        resolution: 256,
        padding: 2,
        texels_per_unit: Some(30.0),
    };
    for (name, (positions, indices)) in [("grid", grid()), ("cube", cube())] {
        let atlas = unwrap(&positions, &indices, &options).unwrap();
        check(name, &positions, &indices, &atlas);
        assert_eq!((atlas.width, atlas.height), (256, 256), "{name}");
        for t in atlas.indices.chunks_exact(3) {
            assert!(
                uv_area2(&atlas, t).abs() > 1.0,
                "{name}: a collapsed triangle"
            );
        }
    }
    // The flat grid needs no seam; the closed cube cannot be flattened whole.
    let (positions, indices) = grid();
    assert_eq!(
        unwrap(&positions, &indices, &options)
            .unwrap()
            .vertices
            .len(),
        9
    );
    let (positions, indices) = cube();
    assert!(
        unwrap(&positions, &indices, &options)
            .unwrap()
            .vertices
            .len()
            > 8
    );
}

#[test]
fn a_given_scale_is_kept_and_the_result_is_deterministic() {
    let (positions, indices) = cube();
    let options = TEN_PER_UNIT;
    let a = unwrap(&positions, &indices, &options).unwrap();
    check("cube", &positions, &indices, &a);
    assert_eq!(a.texels_per_unit, 10.0);
    // A face of side 2 at 10 texels per unit spans about 20 texels.
    for t in a.indices.chunks_exact(3) {
        let area = uv_area2(&a, t).abs() / 2.0;
        assert!((area - 200.0).abs() < 20.0, "{area} texels² for 200");
    }
    assert_eq!(unwrap(&positions, &indices, &options).unwrap(), a);
}

#[test]
fn degenerate_faces_keep_their_place_outside_every_chart() {
    let (mut positions, mut indices) = grid();
    // A sliver with a repeated vertex between the grid's triangles.
    indices.splice(6..6, [0, 0, 1]);
    let atlas = unwrap(&positions, &indices, &Options::default()).unwrap();
    assert_eq!(atlas.indices.len(), indices.len());
    let sliver = &atlas.indices[6..9];
    assert!(
        sliver
            .iter()
            .all(|&i| atlas.vertices[i as usize].atlas_index.is_none())
    );
    for (k, (&out, &input)) in atlas.indices.iter().zip(&indices).enumerate() {
        assert_eq!(atlas.vertices[out as usize].xref, input, "corner {k}");
    }
    // No triangles: nothing to do.
    positions.truncate(9);
    let empty = unwrap(&positions, &[], &Options::default()).unwrap();
    assert!(empty.vertices.is_empty() && empty.indices.is_empty());
}

#[test]
fn malformed_input_is_refused_before_xatlas_sees_it() {
    let (positions, indices) = grid();
    let options = Options::default();
    assert_eq!(
        unwrap(&positions[..8], &indices, &options),
        Err(Error::PositionsNotTriples(8))
    );
    assert_eq!(
        unwrap(&positions, &indices[..7], &options),
        Err(Error::IndicesNotTriangles(7))
    );
    assert_eq!(
        unwrap(&positions, &[0, 1, 9], &options),
        Err(Error::IndexOutOfRange {
            index: 9,
            vertices: 9
        })
    );
    let mut nan = positions.clone();
    nan[13] = f32::NAN;
    assert_eq!(
        unwrap(&nan, &indices, &options),
        Err(Error::NonFinitePosition(4))
    );
    for bad in [0.0, -1.0, f32::INFINITY] {
        let options = Options {
            texels_per_unit: Some(bad),
            ..options
        };
        assert_eq!(
            unwrap(&positions, &indices, &options),
            Err(Error::InvalidTexelsPerUnit(bad))
        );
    }
}

/// The threads of this process, as Linux counts them.
#[cfg(target_os = "linux")]
fn threads() -> usize {
    std::fs::read_dir("/proc/self/task").unwrap().count()
}

/// xatlas is built without its thread pool, whose shutdown can hang (a lost
/// wake-up in `Destroy`): it charts and packs in the calling thread. Built
/// with it, every unwrap starts sixteen workers, which a watcher sampling the
/// process's threads while the unwraps run would see.
#[cfg(target_os = "linux")]
#[test]
fn xatlas_starts_no_thread_of_its_own() {
    use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
    let (positions, indices) = cube();
    let done = AtomicBool::new(false);
    let most = AtomicUsize::new(0);
    let before = std::thread::scope(|scope| {
        scope.spawn(|| {
            while !done.load(Ordering::Relaxed) {
                most.fetch_max(threads(), Ordering::Relaxed);
            }
        });
        // The watcher is running: this count includes it.
        while most.load(Ordering::Relaxed) == 0 {
            std::thread::yield_now();
        }
        let before = threads();
        for _ in 0..50 {
            unwrap(&positions, &indices, &TEN_PER_UNIT).unwrap();
        }
        done.store(true, Ordering::Relaxed);
        before
    });
    // Other tests of this binary may start or end their own threads meanwhile
    // (a handful at most), never sixteen.
    let most = most.into_inner();
    assert!(
        most < before + 8,
        "{most} threads while unwrapping, {before} before"
    );
}
