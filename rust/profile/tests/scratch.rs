use sssbake_profile::*;
use sssbake_profile::presets::preset;
use std::time::Instant;

#[test]
fn scratch() {
    let skin1 = preset("skin1").unwrap();
    let layers = skin1.layers().unwrap();
    let dip = build_profile(&skin1, Model::Dipole, 6).unwrap();
    let lay = build_profile(&skin1, Model::Layered, 6).unwrap();
    let mp = build_profile(&skin1, Model::Multipole, 6).unwrap();
    println!("totals dipole {:?} layered {:?} multipole {:?}", dip.total_reflectance(), lay.total_reflectance(), mp.total_reflectance());
    for r in [0.001, 0.01, 0.1, 0.5, 1.0, 3.0, 10.0] {
        println!("r {r}: dip {:?} lay {:?}", dip.reflectance(r), lay.reflectance(r));
    }
    println!("dmax dip {:?} lay {:?}", dip.d_max(1e-3), lay.d_max(1e-3));
    println!("enclosed inf dip {:?} lay {:?}", dip.enclosed_reflectance(f64::INFINITY), lay.enclosed_reflectance(f64::INFINITY));
    let t = Instant::now();
    let s3 = preset("skin3layer").unwrap();
    let p = build_profile(&s3, Model::Layered, 6).unwrap();
    println!("skin3 {:?} {:?} in {:?}", p.total_reflectance(), p.total_transmittance(), t.elapsed());
    for r in [0.0001, 0.001, 0.005, 0.01, 0.05, 0.1, 1.0] { println!("  r {r}: {:?}", p.reflectance(r)); }
    println!("enclosed {:?} dmax {:?}", p.enclosed_reflectance(f64::INFINITY), p.d_max(1e-3));
    // DJ05 table 1: mfp 1mm. albedo?
    for thick in [2.0, 10.0, 20.0] {
        let l = Layer { sigma_a: [0.01;3], sigma_s: [0.99;3], g: 0.0, ior: 1.3, thickness_mm: Some(thick) };
        let m = Multipole::new(&l, 1e-6);
        println!("slab {thick}: R {:?} T {:?} poles {:?}", m.total_reflectance()[0], m.total_transmittance()[0], m.pole_pairs());
    }
    let mc = monte_carlo::simulate(layers, &monte_carlo::Settings { photons: 20000, seed: 1, edges_mm: monte_carlo::edges_around(&[0.1, 0.5,1.0,2.0,4.0]) });
    println!("mc skin1 R {:?} ± {:?}, interactions {}", mc.total_reflectance, mc.total_reflectance_stderr, mc.interactions);
    for (i, r) in mc.radii_mm.iter().enumerate() { println!("  {r:.3}: mc {:?} dip {:?}", mc.reflectance[i], dip.reflectance(*r)); }
}
