// The body grid's march off the wall (bodygrid.march) in C++: the same operations on the
// same values in the same order as its NumPy loop (_march_numpy), one row of nodes at a time,
// so that every reference grid is bit-identical to it. Built with -ffp-contract=off (no fused
// multiply-add) and without -ffast-math: each line below is one rounded IEEE operation, as
// each NumPy operation is; exp and hypot are the C library's, as Python's and NumPy's are.
//
// Rows are (ni, 2) arrays of doubles, x and y interleaved. A row's neighbours along it:
// an O-grid's nodes wrap across the seam (node ni - 1 repeats node 0: the neighbours of
// both are nodes ni - 2 and 1); an open row (a C-grid's) repeats its end node for its
// missing neighbour; a closed loop of entries (an O-grid's segments) wraps.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace {

using Row = std::vector<double>;

enum Kind { O_NODES = 0, OPEN = 1, CLOSED = 2 };

// march's constants, in the order of MARCH_CONSTANTS (bodygrid.py)
struct Constants {
    double normal_reach, normal_smoothing, concave_smoothing, row_smoothing_max, spread;
    double rear_reach, substep, max_substeps, spacing_rate, corner_cos;
};

inline std::ptrdiff_t before(std::ptrdiff_t i, std::ptrdiff_t n, Kind kind) {
    if (i > 0) return i - 1;
    return kind == O_NODES ? n - 2 : (kind == CLOSED ? n - 1 : 0);
}

inline std::ptrdiff_t after(std::ptrdiff_t i, std::ptrdiff_t n, Kind kind) {
    if (i < n - 1) return i + 1;
    return kind == O_NODES ? 1 : (kind == CLOSED ? 0 : n - 1);
}

// row_chords: the neighbours' difference halved (whole at an open row's ends)
void chords(const double* p, std::ptrdiff_t n, Kind kind, double* out) {
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        std::ptrdiff_t a = before(i, n, kind), b = after(i, n, kind);
        for (int k = 0; k < 2; ++k) {
            double v = p[2 * b + k] - p[2 * a + k];
            if (kind != OPEN || (i > 0 && i < n - 1)) v *= 0.5;
            out[2 * i + k] = v;
        }
    }
}

// _unit: each vector divided by its length
void unit(double* v, std::ptrdiff_t n) {
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        double h = std::hypot(v[2 * i], v[2 * i + 1]);
        v[2 * i] /= h;
        v[2 * i + 1] /= h;
    }
}

// _smoothed: q + eps (the neighbours' mean - q), eps one a node (eps_stride 1) or one for all
// (eps_stride 0); an O-grid's last node repeats its first, an open row's ends held
void smoothed(const double* q, std::ptrdiff_t n, Kind kind, const double* eps, int eps_stride,
              double* out) {
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        std::ptrdiff_t a = before(i, n, kind), b = after(i, n, kind);
        double e = eps[eps_stride * i];
        for (int k = 0; k < 2; ++k) {
            double v = q[2 * a + k] + q[2 * b + k];
            v *= 0.5;
            v -= q[2 * i + k];
            v *= e;
            v += q[2 * i + k];
            out[2 * i + k] = v;
        }
    }
    if (kind == O_NODES) {
        out[2 * (n - 1)] = out[0];
        out[2 * (n - 1) + 1] = out[1];
    } else {
        out[0] = q[0];
        out[1] = q[1];
        out[2 * (n - 1)] = q[2 * (n - 1)];
        out[2 * (n - 1) + 1] = q[2 * (n - 1) + 1];
    }
}

// _row_normals: unit normals pointing away from the body, a corner's bisector where the row
// turns by more than the corner's angle
void row_normals(const double* p, std::ptrdiff_t n, bool o_grid, double corner_cos, double* out,
                 Row& u) {
    Kind kind = o_grid ? O_NODES : OPEN;
    chords(p, n, kind, out);
    unit(out, n);
    double sx = o_grid ? 1.0 : -1.0, sy = o_grid ? -1.0 : 1.0;  // _TURNS
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        double tx = out[2 * i], ty = out[2 * i + 1];
        out[2 * i] = ty * sx;
        out[2 * i + 1] = tx * sy;
    }
    std::ptrdiff_t m = n - 1;  // segments
    u.resize(2 * m);
    for (std::ptrdiff_t i = 0; i < m; ++i) {
        u[2 * i] = p[2 * (i + 1)] - p[2 * i];
        u[2 * i + 1] = p[2 * (i + 1) + 1] - p[2 * i + 1];
    }
    unit(u.data(), m);
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        double cos;
        std::ptrdiff_t ahead, back;
        if (o_grid) {
            std::ptrdiff_t s = i < m ? i : 0;  // node n - 1's turn is node 0's
            std::ptrdiff_t r = s > 0 ? s - 1 : m - 1;
            cos = u[2 * s] * u[2 * r] + u[2 * s + 1] * u[2 * r + 1];
            ahead = i % m;
            back = i > 0 ? i - 1 : m - 1;
        } else {
            if (i == 0 || i == n - 1) continue;
            cos = u[2 * i] * u[2 * (i - 1)] + u[2 * i + 1] * u[2 * (i - 1) + 1];
            ahead = std::min(i, m - 1);
            back = std::max<std::ptrdiff_t>(i - 1, 0);
        }
        if (cos < corner_cos) {
            double vx = u[2 * ahead] + u[2 * back], vy = u[2 * ahead + 1] + u[2 * back + 1];
            double a = vy * sx, b = vx * sy;
            double h = std::hypot(a, b);
            out[2 * i] = a / h;
            out[2 * i + 1] = b / h;
        }
    }
    if (!o_grid) {
        out[0] = 0.0;
        out[1] = -1.0;
        out[2 * (n - 1)] = 0.0;
        out[2 * (n - 1) + 1] = 1.0;
    }
}

// _converging_rate
double converging_rate(const double* q, const double* nrm, std::ptrdiff_t n) {
    double best = -INFINITY;
    for (std::ptrdiff_t i = 0; i + 1 < n; ++i) {
        double ex = q[2 * (i + 1)] - q[2 * i], ey = q[2 * (i + 1) + 1] - q[2 * i + 1];
        double dx = nrm[2 * (i + 1)] - nrm[2 * i], dy = nrm[2 * (i + 1) + 1] - nrm[2 * i + 1];
        double num = dx * ex;
        num += dy * ey;
        double den = ex * ex;
        den += ey * ey;
        double r = -num / den;
        if (std::isnan(r)) return NAN;
        best = std::max(best, r);
    }
    return best;
}

// _count: sub-steps of at most SUBSTEP / rate in a step; -1 where Python's ceil would raise
long count(double step, double rate, const Constants& c) {
    double x = step * rate;
    x /= c.substep;
    if (!std::isfinite(x)) return -1;
    double up = std::ceil(x);
    return (long)std::min(c.max_substeps, std::max(1.0, up));
}

// np.interp(x, xp, fp) for xp ascending, as NumPy computes it
double interp(double x, const double* xp, const double* fp, std::ptrdiff_t n) {
    if (x < xp[0]) return fp[0];
    if (x > xp[n - 1]) return fp[n - 1];
    std::ptrdiff_t j = std::upper_bound(xp, xp + n, x) - xp - 1;
    if (j == n - 1 || xp[j] == x) return fp[j];
    double slope = (fp[j + 1] - fp[j]) / (xp[j + 1] - xp[j]);
    double v = slope * (x - xp[j]);
    return v + fp[j];
}

// redistribute: the row's nodes slid along it to its smoothed spacing
void redistribute(double* q, std::ptrdiff_t n, double eps, bool closed, int passes, Row& work) {
    std::ptrdiff_t m = n - 1;
    work.assign(6 * n + 2 * m, 0.0);
    double* seg = work.data();
    double* ds = seg + m;
    double* step = ds + m;
    double* s_old = step + n;
    double* s_new = s_old + n;
    double* coord = s_new + n;  // x then y of the row, each contiguous
    for (std::ptrdiff_t i = 0; i < m; ++i) {
        seg[i] = std::hypot(q[2 * (i + 1)] - q[2 * i], q[2 * (i + 1) + 1] - q[2 * i + 1]);
        ds[i] = seg[i];
    }
    s_old[0] = 0.0;
    for (std::ptrdiff_t i = 0; i < m; ++i) s_old[i + 1] = s_old[i] + seg[i];
    Kind kind = closed ? CLOSED : OPEN;
    for (int p = 0; p < passes; ++p) {
        for (std::ptrdiff_t i = 0; i < m; ++i) {
            double v = ds[before(i, m, kind)] + ds[after(i, m, kind)];
            v *= 0.5;
            v -= ds[i];
            v *= eps;
            v += ds[i];
            step[i] = v;
        }
        std::copy(step, step + m, ds);
    }
    s_new[0] = 0.0;
    for (std::ptrdiff_t i = 0; i < m; ++i) s_new[i + 1] = s_new[i] + ds[i];
    double scale = s_old[m] / s_new[m];
    for (std::ptrdiff_t i = 0; i < n; ++i) s_new[i] *= scale;
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        coord[i] = q[2 * i];
        coord[n + i] = q[2 * i + 1];
    }
    double x0 = q[0], y0 = q[1], xn = q[2 * m], yn = q[2 * m + 1];
    for (std::ptrdiff_t i = 0; i < n; ++i) {
        q[2 * i] = interp(s_new[i], s_old, coord, n);
        q[2 * i + 1] = interp(s_new[i], s_old, coord + n, n);
    }
    q[0] = x0;
    q[1] = y0;
    q[2 * m] = xn;
    q[2 * m + 1] = yn;
}

}  // namespace

extern "C" {

// Rows 2 .. nrows - 1 of the march (rows 0 and 1, the wall and the first row, are in
// ``out`` already), as bodygrid._march_numpy marches them. ``corner`` and ``rear`` may be
// null (no blunt C-grid base; an O-grid). Returns 0, or 1 where a sub-step count is not
// finite (the caller runs the NumPy loop, which raises there).
int march_rows(long ni, long nrows, const double* dist, double scale, int o_grid, int passes,
               double tangent, long n_wake, const double* spacing0, const double* corner,
               const unsigned char* free, const double* rear, const double* turn_length,
               const double* vertical, const double* constants, double* out) {
    const Constants c{constants[0], constants[1], constants[2], constants[3], constants[4],
                      constants[5], constants[6], constants[7], constants[8], constants[9]};
    std::ptrdiff_t n = ni;
    Kind kind = o_grid ? O_NODES : OPEN;
    const double* inner = out;
    Row q(out + 2 * n, out + 4 * n), nrm(2 * n), tmp(2 * n), tmp2(2 * n), u, work;
    Row weight(n), eps(2 * n), conc(2 * n);
    for (long j = 2; j < nrows; ++j) {
        double step = dist[j] - dist[j - 1];
        row_normals(q.data(), n, o_grid, c.corner_cos, nrm.data(), u);
        // _substeps
        double rate = converging_rate(q.data(), nrm.data(), n);
        chords(q.data(), n, kind, tmp.data());
        double smallest = INFINITY;
        for (std::ptrdiff_t i = 0; i < n; ++i)
            if (free[i]) smallest = std::min(smallest, std::hypot(tmp[2 * i], tmp[2 * i + 1]));
        double spacing = c.spacing_rate / smallest;
        long subs = count(step, std::max(rate, spacing), c);
        if (subs < 0) return 1;
        double start = dist[j - 1], length = step, marched = 0.0;
        long k = 0;
        while (k < subs) {
            if (k) row_normals(q.data(), n, o_grid, c.corner_cos, nrm.data(), u);
            if (rate > 0 && marched > 1 / rate - length / subs / c.substep) {
                rate = converging_rate(q.data(), nrm.data(), n);
                marched = 0.0;
                long more = count(length * (subs - k) / subs, rate, c);
                if (more < 0) return 1;
                if (more > subs - k) {
                    start = start + length * k / subs;
                    length = length * (subs - k) / subs;
                    subs = std::min(more, (long)c.max_substeps);
                    k = 0;
                }
            }
            k += 1;
            marched += length / subs;
            double d = start + length * k / subs;
            double grow = 1 - std::exp(-d / (c.normal_reach * scale));
            // the normals smoothed
            double eps_n = c.normal_smoothing * grow;
            if (corner)
                for (std::ptrdiff_t i = 0; i < n; ++i)
                    weight[i] = c.normal_smoothing * std::max(corner[i], grow);
            for (int p = 0; p < passes; ++p) {
                smoothed(nrm.data(), n, kind, corner ? weight.data() : &eps_n, corner ? 1 : 0,
                         tmp.data());
                unit(tmp.data(), n);
                nrm.swap(tmp);
            }
            if (rear) {
                double fade = std::exp(-d / (c.rear_reach * scale));
                for (std::ptrdiff_t i = 0; i < n; ++i) {
                    double turn = std::min(1.0, (d - dist[1]) / turn_length[i]);
                    turn = rear[i] * turn;
                    turn = rear[i] > 0 ? 1 - (1 - turn) * fade : 0.0;
                    for (int k2 = 0; k2 < 2; ++k2) {
                        double a = (1 - turn) * nrm[2 * i + k2];
                        double b = turn * vertical[2 * i + k2];
                        nrm[2 * i + k2] = a + b;
                    }
                }
                unit(nrm.data(), n);
            }
            double h = length / subs;
            for (std::ptrdiff_t i = 0; i < 2 * n; ++i) q[i] = q[i] + nrm[i] * h;
            // the row's shrink: how much smoothing along it
            chords(q.data(), n, kind, tmp.data());
            for (std::ptrdiff_t i = 0; i < n; ++i) {
                double shrink = 1 - std::hypot(tmp[2 * i], tmp[2 * i + 1]) / spacing0[i];
                double concave =
                    std::max(std::min(c.row_smoothing_max, c.concave_smoothing * shrink), 0.0);
                conc[2 * i] = conc[2 * i + 1] = concave;
                bool wake = !o_grid && (i < n_wake || i >= n - n_wake);
                double e = wake ? 0.0 : grow * concave;
                if (corner) e = std::max(e, corner[i] * concave);
                eps[2 * i] = eps[2 * i + 1] = e;
            }
            for (int p = 0; p < passes; ++p) {
                smoothed(q.data(), n, kind, eps.data(), 2, tmp.data());
                q.swap(tmp);
                if (tangent) {
                    double e = tangent * grow;
                    smoothed(q.data(), n, kind, &e, 0, tmp.data());  // the slide's target
                    chords(q.data(), n, kind, tmp2.data());
                    unit(tmp2.data(), n);
                    for (std::ptrdiff_t i = 0; i < n; ++i) {
                        double sx = tmp[2 * i] - q[2 * i], sy = tmp[2 * i + 1] - q[2 * i + 1];
                        sx *= tmp2[2 * i];
                        sy *= tmp2[2 * i + 1];
                        double along = sx + sy;
                        q[2 * i] = q[2 * i] + tmp2[2 * i] * along;
                        q[2 * i + 1] = q[2 * i + 1] + tmp2[2 * i + 1] * along;
                    }
                }
            }
            if (o_grid) {
                redistribute(q.data(), n, c.spread * grow, true, passes, work);
            } else {  // the body's columns (the wake's run straight)
                redistribute(q.data() + 2 * n_wake, n - 2 * n_wake, c.spread * grow, false,
                             passes, work);
                q[0] = inner[0] + 0.0;
                q[1] = inner[1] + -d;
                q[2 * (n - 1)] = inner[2 * (n - 1)] + 0.0;
                q[2 * (n - 1) + 1] = inner[2 * (n - 1) + 1] + d;
            }
        }
        std::copy(q.begin(), q.end(), out + 2 * n * j);
    }
    return 0;
}
}
