//! The camera's numbers as the window and `bench` show them: the short decimals a user set,
//! not what arithmetic on them left. A focal length typed as 101 is stored as a fraction of
//! the image width (101 / 794 × 794 is 101.00000000000003), a zoom multiplies it by 1.1 per
//! wheel line, a yaw typed as 7.3° is stored in radians (`to_degrees` gives
//! 7.300000000000001). The window renders with the clean values it shows, so a copied
//! command re-reads to the same camera.

/// `x`, or the shortest decimal within a few ulps of it (what arithmetic on a short decimal
/// leaves is that far off it).
pub fn clean(x: f64) -> f64 {
    if !x.is_finite() || x == 0.0 {
        return x;
    }
    let near = 4.0 * f64::EPSILON * x.abs();
    shortest(x, 15, |d| (d - x).abs() <= near).unwrap_or(x)
}

/// `radians` in degrees, as the shortest decimal whose `to_radians` is `radians` again: the
/// command line and a view file read degrees back that way.
pub fn degrees(radians: f64) -> f64 {
    let exact = radians.to_degrees();
    shortest(exact, 17, |d| d.to_radians() == radians).unwrap_or(exact)
}

/// Where the camera rays leave from where that is not the position shown to the panel's
/// three decimals: the position rounded to f32, as the renderer takes it (at 10¹² the
/// position field read 1000000000000.00 while the rays left 4096 units away, and a slow
/// flight moved the field but never the image).
pub fn rays_leave_from(position: [f64; 3]) -> Option<[f32; 3]> {
    let from = position.map(|c| c as f32);
    let shown_apart = (position.iter().zip(&from)).any(|(&c, &f)| (c - f64::from(f)).abs() >= 5e-4);
    shown_apart.then_some(from)
}

/// The shortest decimal form of `x`, of 1 to `most` significant digits, that `keeps`.
fn shortest(x: f64, most: usize, keeps: impl Fn(f64) -> bool) -> Option<f64> {
    (1..=most)
        .filter_map(|digits| format!("{x:.*e}", digits - 1).parse::<f64>().ok())
        .find(|&d| keeps(d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drift_is_taken_away_and_other_values_are_kept() {
        let typed = 101.0 / 794.0 * 794.0;
        assert_ne!(typed, 101.0);
        assert_eq!(clean(typed), 101.0);
        assert_eq!(clean(1.1 * 794.0), 873.4);
        assert_eq!(clean(873.4172631), 873.4172631);
        let third = 794.0 / 3.0;
        assert_eq!(clean(third), third);
        assert_eq!(clean(-0.1 * 3.0), -0.3);
    }

    #[test]
    fn the_rays_origin_is_named_where_f32_moves_it_in_sight() {
        assert_eq!(
            rays_leave_from([0.0, 0.0, -3.001]),
            None,
            "-3.001 within 1e-7"
        );
        assert_eq!(rays_leave_from([1234.567, 12.3, 0.0]), None);
        let off = rays_leave_from([1e5 + 0.1, 0.0, 0.0]);
        assert_eq!(
            off,
            Some([100_000.1, 0.0, 0.0]),
            "1e5 + 0.1 is 0.0016 from its f32"
        );
        let at_1e12 = rays_leave_from([1e12, 0.3, 0.0]);
        assert_eq!(at_1e12, Some([999_999_995_904.0, 0.3, 0.0]));
        assert_eq!(
            rays_leave_from([1e7 + 0.1, 0.0, 0.0]),
            Some([1e7, 0.0, 0.0])
        );
    }

    #[test]
    fn degrees_read_back_to_the_same_radians() {
        let yaw = 7.3f64.to_radians();
        assert_eq!(degrees(yaw), 7.3);
        for r in [0.1234567, -2.5, 1e-9, std::f64::consts::PI] {
            assert_eq!(degrees(r).to_radians(), r, "{r}");
        }
    }
}
