//! The camera's numbers as the window shows and copies them: the short decimals a user set,
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
    (1..=15)
        .filter_map(|digits| format!("{x:.*e}", digits - 1).parse::<f64>().ok())
        .find(|d| (d - x).abs() <= near)
        .unwrap_or(x)
}

/// `radians` in degrees, as the shortest decimal whose `to_radians` is `radians` again: the
/// command line and a view file read degrees back that way.
pub fn degrees(radians: f64) -> f64 {
    let exact = radians.to_degrees();
    (1..=17)
        .filter_map(|digits| format!("{exact:.*e}", digits - 1).parse::<f64>().ok())
        .find(|d| d.to_radians() == radians)
        .unwrap_or(exact)
}

/// The library's `raylab render` line `command` with `focal` as its `--focal`: the library
/// derives that flag from the view's field of view (through tan and atan), an ulp or so off
/// the focal length the window renders with (101.00000000000003 for 101).
pub fn with_focal(command: &str, focal: f64) -> String {
    // (The last one: only numbers, the controls' names and the output file, `raylab.png`,
    // follow it; the scene's path before it may hold anything.)
    let flag = " --focal=";
    let Some(at) = command.rfind(flag).map(|i| i + flag.len()) else {
        return command.to_string();
    };
    let end = command[at..].find(' ').map_or(command.len(), |i| at + i);
    format!("{}{focal}{}", &command[..at], &command[end..])
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
    fn degrees_read_back_to_the_same_radians() {
        let yaw = 7.3f64.to_radians();
        assert_eq!(degrees(yaw), 7.3);
        for r in [0.1234567, -2.5, 1e-9, std::f64::consts::PI] {
            assert_eq!(degrees(r).to_radians(), r, "{r}");
        }
    }

    #[test]
    fn the_focal_flag_is_replaced_and_nothing_else() {
        let command = "raylab render --scene='a --focal=3.obj' --yaw=0 --focal=100.00000000000001 \
                       --width=794 --spp=2 -o raylab.png";
        assert_eq!(
            with_focal(command, 100.0),
            "raylab render --scene='a --focal=3.obj' --yaw=0 --focal=100 --width=794 --spp=2 \
             -o raylab.png"
        );
    }
}
