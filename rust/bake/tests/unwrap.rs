//! Unwrapping meshes without usable UVs with xatlas.

mod shapes;
use shapes::*;
use sssbake::surface::unwrap::unwrap;
use sssbake::{analyse_uvs, rasterize};

#[test]
fn unwrapped_meshes_bake_like_the_surface() {
    for mut mesh in [sphere(15.0, 24, 48), cube(10.0), overlapping_quads()] {
        let area = mesh.area();
        mesh.uvs = None;
        let unwrapped = unwrap(&mesh, 512, 4).unwrap();
        assert!(
            (unwrapped.area() - area).abs() < 1e-6 * area,
            "{}: the surface changed",
            mesh.name
        );
        let report = analyse_uvs(&unwrapped, None, 512);
        assert!(report.usable(), "{}: {}", mesh.name, report.verdict());
        let surfels = rasterize(&unwrapped, unwrapped.uvs.as_ref().unwrap(), 1024);
        assert!(
            (surfels.total_area() - area).abs() < 0.01 * area,
            "{}: {} vs {area}",
            mesh.name,
            surfels.total_area()
        );
    }
}

#[test]
fn unwrapping_is_deterministic_and_respects_padding() {
    let mut mesh = cube(10.0);
    mesh.uvs = None;
    let (a, b) = (
        unwrap(&mesh, 256, 4).unwrap(),
        unwrap(&mesh, 256, 4).unwrap(),
    );
    assert_eq!(a.uvs, b.uvs);
    assert_eq!(a.triangles, b.triangles);
    // Charts are the groups of triangles joined by shared vertices (seams
    // split vertices). With 4 texels of padding no texel of one chart may
    // touch a texel of another, even counting partly covered texels.
    let mut chart: Vec<usize> = (0..a.positions.len()).collect();
    fn root(chart: &mut [usize], mut i: usize) -> usize {
        while chart[i] != i {
            chart[i] = chart[chart[i]];
            i = chart[i];
        }
        i
    }
    for t in &a.triangles {
        for k in 1..3 {
            let (x, y) = (
                root(&mut chart, t[0] as usize),
                root(&mut chart, t[k] as usize),
            );
            chart[x] = y;
        }
    }
    let surfels = rasterize(&a, a.uvs.as_ref().unwrap(), 256);
    let texel_chart = |texel: usize| {
        let s = surfels.index[texel];
        (s != u32::MAX).then(|| a.triangles[surfels.triangle[s as usize] as usize][0] as usize)
    };
    let mut charts = std::collections::HashSet::new();
    for y in 0..255usize {
        for x in 0..255usize {
            let Some(here) = texel_chart(y * 256 + x) else {
                continue;
            };
            let here = root(&mut chart, here);
            charts.insert(here);
            for (dx, dy) in [(1, 0), (0, 1), (1, 1)] {
                if let Some(there) = texel_chart((y + dy) * 256 + x + dx) {
                    assert_eq!(
                        root(&mut chart, there),
                        here,
                        "charts touch at texel ({x}, {y})"
                    );
                }
            }
        }
    }
    assert!(charts.len() >= 2, "a cube needs more than one chart");
}

#[test]
fn slivers_do_not_stop_the_unwrap() {
    // Pole triangles of a fine lat-long sphere are slivers xatlas leaves out.
    let mut mesh = sphere(10.0, 30, 60);
    let area = mesh.area();
    mesh.uvs = None;
    let unwrapped = unwrap(&mesh, 1024, 4).unwrap();
    let surfels = rasterize(&unwrapped, unwrapped.uvs.as_ref().unwrap(), 1024);
    assert!(
        (surfels.total_area() - area).abs() < 0.01 * area,
        "{} vs {area}",
        surfels.total_area()
    );
}
