/* The start-up ramp r(t) = (1 - cos(pi t / T)) / 2 for 0 <= t < T, 0 before 0, 1 from T on (T <= 0: no ramp,
 * r = 1); its first derivative is continuous (hydro_fmu.waves.Ramp). */
#include <math.h>

#include "hydro_internal.h"

static const double PI = 3.14159265358979323846;

double hydro_ramp(double duration, double t)
{
    if (duration <= 0.0 || t >= duration)
        return 1.0;
    return 0.5 * (1.0 - cos(PI * (t > 0.0 ? t : 0.0) / duration));
}

double hydro_ramp_rate(double duration, double t)
{
    if (duration <= 0.0 || t >= duration || t <= 0.0)
        return 0.0;
    return 0.5 * PI / duration * sin(PI * t / duration);
}
