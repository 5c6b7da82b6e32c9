//! Convergence study of a single-edge-cracked strip (the development study behind the mesh
//! defaults; env `EDGES=b,r,t,l` per-edge sizes, `GRADE=g` outline grading away from the crack
//! plane, `NORECON=1` plain constant elements):
//! `cargo run --release -p pdbem-bem --example sent_study -- LENGTH W a h_outline h_crack [h_tip r_tip]`
use pdbem_bem::mesh::{CrackSpec, FaceMode, LoopSpec, TipRefinement};
use pdbem_bem::post::sif::{analyze_tips, cmod, SifOptions};
use pdbem_bem::post::{Background, FieldEvaluator};
use pdbem_bem::{Bc, BemSystem, Material, MeshBuilder, Plane, SolveParams, V2};
use std::f64::consts::PI;

fn tada(a: f64, w: f64) -> f64 {
    let x = a / w;
    let t = PI * x / 2.0;
    (2.0 / (PI * x) * t.tan()).sqrt() * (0.752 + 2.02 * x + 0.37 * (1.0 - t.sin()).powi(3))
        / t.cos()
}

fn main() {
    let args: Vec<f64> = std::env::args()
        .skip(1)
        .map(|s| s.parse().unwrap())
        .collect();
    let (len, w, a, ho, hc) = (args[0], args[1], args[2], args[3], args[4]);
    let tip = (args.len() > 6).then(|| TipRefinement {
        size: args[5],
        radius: args[6],
    });
    let mat = Material::new(1e4, 1.0 / 3.0, Plane::Stress).unwrap();
    let sigma = 0.5;
    let mut b = MeshBuilder::new();
    if let Ok(g) = std::env::var("GRADE") {
        // h(d) = min(ho, hc + g d) with d the distance from the crack plane x = len/2.
        let g: f64 = g.parse().unwrap();
        // Distance from the crack plane x = len / 2.
        let hsize = |x: f64, _y: f64| (hc + g * (x - len / 2.0).abs()).min(ho);
        let mut pts = Vec::new();
        let corners = [
            V2::new(0.0, 0.0),
            V2::new(len, 0.0),
            V2::new(len, w),
            V2::new(0.0, w),
        ];
        for k in 0..4 {
            let (p, q) = (corners[k], corners[(k + 1) % 4]);
            let l = (q - p).norm();
            let mut s = 0.0;
            while s < l - 1e-9 {
                pts.push(p + (q - p) * (s / l));
                let x = p + (q - p) * (s / l);
                let mut hh = hsize(x.x, x.y);
                if l - s < 1.5 * hh {
                    hh = l - s;
                }
                s += hh;
            }
        }
        let n = pts.len();
        b.add_loop(LoopSpec {
            points: pts,
            edge_groups: vec!["edge".into(); n],
            edge_sizes: vec![f64::INFINITY; n],
            is_hole: false,
        });
    } else {
        b.add_loop(LoopSpec {
            points: vec![
                V2::new(0.0, 0.0),
                V2::new(len, 0.0),
                V2::new(len, w),
                V2::new(0.0, w),
            ],
            edge_groups: ["bottom", "right", "top", "left"]
                .map(String::from)
                .to_vec(),
            edge_sizes: std::env::var("EDGES")
                .map(|v| v.split(',').map(|x| x.parse().unwrap()).collect())
                .unwrap_or(vec![ho; 4]),
            is_hole: false,
        });
    }
    b.add_crack(CrackSpec {
        name: "c".into(),
        points: vec![V2::new(len / 2.0, w), V2::new(len / 2.0, w - a)],
        faces: FaceMode::Coincident,
        element_size: hc,
        tip,
    });
    let mesh = b.build().unwrap();
    let bcs: Vec<[Bc; 2]> = mesh
        .elements
        .iter()
        .map(|e| {
            let gname = mesh.groups[e.group].as_str();
            let tx = if ["edge", "left", "right", "top", "bottom"].contains(&gname) {
                if e.normal.x < -0.9 {
                    -sigma
                } else if e.normal.x > 0.9 {
                    sigma
                } else {
                    0.0
                }
            } else {
                0.0
            };
            [Bc::Traction(tx), Bc::Traction(0.0)]
        })
        .collect();
    let params = SolveParams {
        reconstruct: std::env::var("NORECON").is_err(),
        ..Default::default()
    };
    let sys = BemSystem::new(&mesh, &mat, &bcs, &params).unwrap();
    let sol = sys.solve().unwrap();
    let ev = FieldEvaluator::new(&mesh, &mat, &sol, Background::default());
    let t = &analyze_tips(&mesh, &ev, &sol, &SifOptions::default()).unwrap()[0];
    let k = sigma * (PI * a).sqrt() * tada(a, w);
    let x = a / w;
    let v = (1.46 + 3.42 * (1.0 - (PI * x / 2.0).cos())) / (PI * x / 2.0).cos().powi(2);
    let cm = 4.0 * sigma * a / mat.e_prime() * v;
    println!(
        "N={} k_cod_err={:+.3}% k_m_err={:+.3}% cmod_err={:+.3}% cond={:.0} asm={:.2}s fac={:.2}s lambda={:?}",
        mesh.len(),
        100.0 * (t.k1_cod / k - 1.0),
        100.0 * (t.k1_m / k - 1.0),
        100.0 * (cmod(&mesh, &sol, 0).unwrap() / cm - 1.0),
        sys.info().condition,
        sys.info().assembly_s,
        sys.info().factor_s,
        sol.lambda
    );
}
