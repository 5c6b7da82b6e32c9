//! Williams near-tip fields of unit K (modes I and II) in the tip frame: the auxiliary
//! fields of the interaction integral ([`super::sif`], [`super::face_traction`]).
//! $u = \frac{K}{2\mu}\sqrt{\frac{r}{2\pi}}\,g(\theta, \kappa)$,
//! $\sigma = \frac{K}{\sqrt{2\pi r}} f(\theta)$ (e.g. Anderson, *Fracture Mechanics*).

use std::f64::consts::PI;

/// Williams near-tip fields for unit K: (displacement, stress [s11, s22, s12]) in the tip
/// frame, mode I (`mode` = 1) or II.
pub fn williams(mode: u8, r: f64, th: f64, mu: f64, kappa: f64) -> ([f64; 2], [f64; 3]) {
    let (h, t3) = (0.5 * th, 1.5 * th);
    let (s, c) = h.sin_cos();
    let f = 1.0 / (2.0 * PI * r).sqrt();
    let g = (r / (2.0 * PI)).sqrt() / (2.0 * mu);
    if mode == 1 {
        (
            [
                g * c * (kappa - 1.0 + 2.0 * s * s),
                g * s * (kappa + 1.0 - 2.0 * c * c),
            ],
            [
                f * c * (1.0 - s * t3.sin()),
                f * c * (1.0 + s * t3.sin()),
                f * s * c * t3.cos(),
            ],
        )
    } else {
        (
            [
                g * s * (kappa + 1.0 + 2.0 * c * c),
                -g * c * (kappa - 1.0 - 2.0 * s * s),
            ],
            [
                -f * s * (2.0 + c * t3.cos()),
                f * s * c * t3.cos(),
                f * c * (1.0 - s * t3.sin()),
            ],
        )
    }
}
