#!/usr/bin/env python3
"""exact.py with one classic bug: an epsilon on the determinant.

python3 det_epsilon.py scene.txt rays.txt

The bug: Möller–Trumbore's guard against parallel rays, |det| < 1e-8 taken as no hit,
where only det = 0 is parallel: det = e1·(d × e2) scales with the triangle's area and |d|, so a
small triangle (or a grazing ray) is lost whole.
"""
import sys
from fractions import Fraction as Q
from math import isqrt


def sqrt(x):  # exact where x is a square, else within 2^-200 relative
    n, d = x.numerator * x.denominator, x.denominator
    r = isqrt(n)
    return Q(r, d) if r * r == n else Q(isqrt(n << 400), d << 200)


def sub(a, b): return [x - y for x, y in zip(a, b)]
def dot(a, b): return sum(x * y for x, y in zip(a, b))
def cross(a, b): return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


PRECISION = sys.argv[3] if len(sys.argv) > 3 else "f32"  # a third argument f64 reads in double


def num(word):  # the number as raylab reads it: the nearest f32 (or f64) value, ties to even
    x = Q(word)
    if PRECISION == "f64" or x == 0:
        return Q(float(x))  # (float of a Fraction rounds correctly)
    a = abs(x)
    e = a.numerator.bit_length() - a.denominator.bit_length()  # 2^(e-1) < a < 2^(e+1)
    ulp = max(e - 24 + (a >= Q(2) ** e), -149)  # f32's 24 bits, subnormals' 2^-149
    m = a / Q(2) ** ulp
    n, r = divmod(m.numerator, m.denominator)
    n += 2 * r > m.denominator or (2 * r == m.denominator and n % 2 == 1)
    return (1 if x > 0 else -1) * n * Q(2) ** ulp


def hits(kind, v, o, d):  # the ray parameters where o + t·d meets the primitive
    if kind == "tri":  # o + t·d = v0 + b1·e1 + b2·e2 by Cramer's rule (closed, edge-on misses)
        e1, e2, s = sub(v[3:6], v[:3]), sub(v[6:], v[:3]), sub(o, v[:3])
        p, q = cross(d, e2), cross(s, e1)
        det = dot(e1, p)
        if abs(det) < Q(1, 10**8):  # BUG: an absolute epsilon for == 0
            return []
        b1, b2 = dot(s, p) / det, dot(d, q) / det
        return [dot(e2, q) / det] if b1 >= 0 and b2 >= 0 and b1 + b2 <= 1 else []
    oc = sub(o, v[:3])  # |o + t·d − c|² = r²: a·t² + 2b·t + c = 0 (a tangent touch hits)
    a, b, c = dot(d, d), dot(d, oc), dot(oc, oc) - v[3] ** 2
    disc = b * b - a * c
    return [] if disc < 0 else [(-b - sqrt(disc)) / a, (-b + sqrt(disc)) / a]


shapes = [(w[0], [num(x) for x in w[1:]]) for w in map(str.split, open(sys.argv[1])) if w and w[0] in ("tri", "sphere")]
for w in map(str.split, open(sys.argv[2])):
    if not w or w[0].startswith("#"):
        continue
    o, d = [num(x) for x in w[:3]], [num(x) for x in w[3:6]]
    tmin, tmax = None if w[6] == "-inf" else num(w[6]), None if w[7] == "inf" else num(w[7])
    best = None
    for i, (kind, v) in enumerate(shapes):  # strictly nearer only: an exact tie keeps the lower index
        t = next((t for t in hits(kind, v, o, d) if (tmin is None or tmin < t) and (tmax is None or t < tmax)), None)
        if t is not None:
            best, tmax = (t, i), t
    print(f"hit {float(best[0])!r} {best[1]}" if best else "miss")
