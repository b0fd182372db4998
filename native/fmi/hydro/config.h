/* The native hydrodynamics FMU's configuration: model identifier, value references, resource file.
 *
 * Value references are computed from the model's number of selected degrees of freedom n (read from the runtime
 * input at instantiation), so one binary serves every scene; hydro_fmu/native_fmu.py writes the model description
 * with the same scheme. Index i = 0 .. n-1 counts the selected DOFs body by body; (k, l) entries of n x n
 * matrices are at k * n + l. The binary is the same for every scene: the GUID / instantiation token it checks is
 * the one stored with the runtime input (array fmu.token, the model description's), so the compiled library can
 * be cached by its sources. */
#ifndef WEC_FMI_HYDRO_CONFIG_H
#define WEC_FMI_HYDRO_CONFIG_H

#define MODEL_IDENTIFIER wec_hydro_native
#define HYDRO_RESOURCE "hydro.wecrt" /* the runtime input in resources/ */

#define VR_ELEVATION 1u              /* wave.elevation at the origin (m) */
#define VR_WORK 2u                   /* energy.*_work, 4 values: excitation, radiation, hydrostatic, viscous (J) */
#define VR_CONSTANT 100u             /* constants fixed at build time (array fmu.constants of the input) */
#define VR_X 1000u                   /* x[i] inputs */
#define VR_V 2000u                   /* v[i] inputs */
#define VR_F 3000u                   /* total force F[i] */
#define VR_F_EXC 4000u               /* its parts: excitation, radiation memory, hydrostatic, viscous */
#define VR_F_RAD 5000u
#define VR_F_HS 6000u
#define VR_F_VISC 7000u
#define VR_F0 8000u                  /* linearised force interface */
#define VR_F0_RATE 9000u
#define VR_DF_DX 100000u             /* + k * n + l */
#define VR_DF_DV 200000u
#define VR_A_INF 300000u             /* infinite-frequency added mass (calculated parameter) */
#define VR_BLOCK 1000u               /* width of each per-DOF block: n < 1000 */
#define VR_MATRIX 100000u            /* width of each matrix block: n * n < 100000 */

/* FMI 3.0 array variables (one value reference each; scalars as above) */
#define VR3_X 11u
#define VR3_V 12u
#define VR3_F 13u
#define VR3_F_EXC 14u
#define VR3_F_RAD 15u
#define VR3_F_HS 16u
#define VR3_F_VISC 17u
#define VR3_F0 18u
#define VR3_F0_RATE 19u
#define VR3_DF_DX 20u
#define VR3_DF_DV 21u
#define VR3_A_INF 22u
#define VR3_WORK 23u

#endif
