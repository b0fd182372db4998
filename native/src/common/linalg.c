/* Dense linear algebra the runtimes need: LU solve with partial pivoting and the matrix exponential. */
#include <math.h>
#include <string.h>

#include "wec_common.h"

int wec_lu_solve(double *a, size_t n, double *b, size_t m, int64_t *pivots)
{
    for (size_t k = 0; k < n; k++) {
        size_t p = k;
        double best = fabs(a[k * n + k]);
        for (size_t i = k + 1; i < n; i++)
            if (fabs(a[i * n + k]) > best) {
                best = fabs(a[i * n + k]);
                p = i;
            }
        pivots[k] = (int64_t)p;
        if (best == 0.0)
            return 1;
        if (p != k) {
            for (size_t j = 0; j < n; j++) {
                double s = a[k * n + j];
                a[k * n + j] = a[p * n + j];
                a[p * n + j] = s;
            }
            for (size_t j = 0; j < m; j++) {
                double s = b[k * m + j];
                b[k * m + j] = b[p * m + j];
                b[p * m + j] = s;
            }
        }
        double pivot = a[k * n + k];
        for (size_t i = k + 1; i < n; i++) {
            double f = a[i * n + k] / pivot;
            a[i * n + k] = f;
            if (f == 0.0)
                continue;
            for (size_t j = k + 1; j < n; j++)
                a[i * n + j] -= f * a[k * n + j];
            for (size_t j = 0; j < m; j++)
                b[i * m + j] -= f * b[k * m + j];
        }
    }
    for (size_t kk = n; kk-- > 0;) {
        for (size_t j = 0; j < m; j++) {
            double s = b[kk * m + j];
            for (size_t i = kk + 1; i < n; i++)
                s -= a[kk * n + i] * b[i * m + j];
            b[kk * m + j] = s / a[kk * n + kk];
        }
    }
    return 0;
}

/* out = a b (n x n, row-major; out distinct from a and b) */
static void matmul(const double *a, const double *b, double *out, size_t n)
{
    memset(out, 0, n * n * sizeof(double));
    for (size_t i = 0; i < n; i++)
        for (size_t k = 0; k < n; k++) {
            double f = a[i * n + k];
            if (f == 0.0)
                continue;
            for (size_t j = 0; j < n; j++)
                out[i * n + j] += f * b[k * n + j];
        }
}

static double norm1(const double *a, size_t n)
{
    double best = 0.0;
    for (size_t j = 0; j < n; j++) {
        double s = 0.0;
        for (size_t i = 0; i < n; i++)
            s += fabs(a[i * n + j]);
        if (s > best || isnan(s))
            best = s;
    }
    return best;
}

size_t wec_expm_workspace_size(size_t n)
{
    size_t nn;
    if (!wec_mul(n, n, &nn) || !wec_mul(nn, 8, &nn))
        return 0;
    return nn;
}

int wec_expm(const double *a, size_t n, double *out, double *work, int64_t *pivots)
{
    static const double theta[] = {1.495585217958292e-2, 2.539398330063230e-1, 9.504178996162932e-1,
                                   2.097847961257068e0, 5.371920351148152e0};
    static const double b3[] = {120., 60., 12., 1.};
    static const double b5[] = {30240., 15120., 3360., 420., 30., 1.};
    static const double b7[] = {17297280., 8648640., 1995840., 277200., 25200., 1512., 56., 1.};
    static const double b9[] = {17643225600., 8821612800., 2075673600., 302702400., 30270240., 2162160., 110880.,
                                3960., 90., 1.};
    static const double b13[] = {64764752532480000., 32382376266240000., 7771770303897600., 1187353796428800.,
                                 129060195264000., 10559470521600., 670442572800., 33522128640., 1323241920.,
                                 40840800., 960960., 16380., 182., 1.};
    size_t nn = n * n;
    if (n == 0)
        return 0;
    double *s_a = work, *a2 = work + nn, *a4 = work + 2 * nn, *a6 = work + 3 * nn, *u = work + 4 * nn,
           *v = work + 5 * nn, *tmp = work + 6 * nn, *tmp2 = work + 7 * nn;
    double norm = norm1(a, n);
    if (!isfinite(norm))
        return 1;
    int degree = 13;
    const double *b = b13;
    int squarings = 0;
    if (norm <= theta[0]) {
        degree = 3;
        b = b3;
    } else if (norm <= theta[1]) {
        degree = 5;
        b = b5;
    } else if (norm <= theta[2]) {
        degree = 7;
        b = b7;
    } else if (norm <= theta[3]) {
        degree = 9;
        b = b9;
    } else if (norm > theta[4]) {
        squarings = (int)ceil(log2(norm / theta[4]));
        if (squarings < 0)
            squarings = 0;
    }
    double scale = ldexp(1.0, -squarings);
    for (size_t i = 0; i < nn; i++)
        s_a[i] = a[i] * scale;
    matmul(s_a, s_a, a2, n);
    /* u = A (odd part), v = even part */
    if (degree < 13) {
        /* powers A^2, A^4, ... accumulated: u_poly = sum b[2k+1] A^(2k), v = sum b[2k] A^(2k) */
        memset(tmp, 0, nn * sizeof(double)); /* odd polynomial in A^2 */
        memset(v, 0, nn * sizeof(double));
        for (size_t i = 0; i < n; i++) {
            tmp[i * n + i] = b[1];
            v[i * n + i] = b[0];
        }
        memcpy(a4, a2, nn * sizeof(double)); /* current even power A^(2k), k = 1 */
        for (int k = 1; 2 * k <= degree; k++) {
            for (size_t i = 0; i < nn; i++) {
                tmp[i] += b[2 * k + 1] * a4[i];
                v[i] += b[2 * k] * a4[i];
            }
            if (2 * (k + 1) <= degree) {
                matmul(a4, a2, a6, n);
                memcpy(a4, a6, nn * sizeof(double));
            }
        }
        matmul(s_a, tmp, u, n);
    } else {
        matmul(a2, a2, a4, n);
        matmul(a4, a2, a6, n);
        for (size_t i = 0; i < nn; i++)
            tmp[i] = b[13] * a6[i] + b[11] * a4[i] + b[9] * a2[i];
        matmul(a6, tmp, tmp2, n);
        for (size_t i = 0; i < nn; i++)
            tmp2[i] += b[7] * a6[i] + b[5] * a4[i] + b[3] * a2[i];
        for (size_t i = 0; i < n; i++)
            tmp2[i * n + i] += b[1];
        matmul(s_a, tmp2, u, n);
        for (size_t i = 0; i < nn; i++)
            tmp[i] = b[12] * a6[i] + b[10] * a4[i] + b[8] * a2[i];
        matmul(a6, tmp, v, n);
        for (size_t i = 0; i < nn; i++)
            v[i] += b[6] * a6[i] + b[4] * a4[i] + b[2] * a2[i];
        for (size_t i = 0; i < n; i++)
            v[i * n + i] += b[0];
    }
    /* (v - u) X = (v + u) */
    for (size_t i = 0; i < nn; i++) {
        tmp[i] = v[i] - u[i];
        out[i] = v[i] + u[i];
    }
    if (wec_lu_solve(tmp, n, out, n, pivots))
        return 1;
    for (int s = 0; s < squarings; s++) {
        matmul(out, out, tmp, n);
        memcpy(out, tmp, nn * sizeof(double));
    }
    for (size_t i = 0; i < nn; i++)
        if (!isfinite(out[i]))
            return 1;
    return 0;
}
