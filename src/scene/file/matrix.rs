//! The check every transform statement of a `.scene` file passes: the matrix after it stays
//! finite and regular in f64.

use glam::DMat4;

/// Refuses the transform statement `words` if the matrix after it, `m`, is not finite or is
/// singular in f64 (scales multiplied past f64's range: `scale 1e-200` twice is 0).
pub(super) fn check_matrix(m: &DMat4, words: &[&str]) -> Result<(), String> {
    let what = words.join(" ");
    if !m.is_finite() {
        return Err(format!(
            "'{what}' makes the transform's matrix not finite in f64 (it passes ±{:e}): \
             every point after it would be infinite",
            f64::MAX
        ));
    }
    // The determinant of the columns each scaled by a power of two (exactly) to a
    // largest entry near 1: 0 only where the matrix is singular in f64. The power goes in
    // two halves, each a normal f64 (for a subnormal largest entry the whole one, up to
    // 2^1074, is not: its reciprocal came out 0 and the column infinite). A zero column is
    // singular; so is a determinant that is not finite (no proof of a regular matrix).
    let pow2 = |e: i32| f64::from_bits(((e + 1023) as u64) << 52);
    let cols = [m.x_axis, m.y_axis, m.z_axis].map(|c| {
        let c = c.truncate();
        let max = c.abs().max_element();
        if max == 0.0 {
            return None;
        }
        let e = -(max.log2().floor() as i32);
        Some(c * pow2(e / 2) * pow2(e - e / 2))
    });
    let det = match cols {
        [Some(a), Some(b), Some(c)] => a.dot(b.cross(c)),
        _ => 0.0,
    };
    if det == 0.0 || !det.is_finite() {
        return Err(format!(
            "'{what}' makes the transform's matrix singular in f64 (its scales multiply \
             below {:e}, to 0): every point after it would collapse",
            f64::from_bits(1)
        ));
    }
    Ok(())
}
