/* A small native one-body heave FMU: an example of a user's own multibody model coupled to the native hydro FMU
 * through the linearised force interface (docs/hosts/native_fmus.md). Value references of model.c. */
#ifndef WEC_FMI_HEAVE_BODY_CONFIG_H
#define WEC_FMI_HEAVE_BODY_CONFIG_H

#define MODEL_IDENTIFIER wec_heave_body
#define HEAVE_BODY_TOKEN "{5e1b7c3a-0d2f-4c61-9a0e-7d1f3b2a9c01}"

#define VR_MASS 1u        /* parameter: body mass (kg) */
#define VR_ADDED_MASS 2u  /* parameter: infinite-frequency added mass (kg) */
#define VR_DAMPING 3u     /* parameter: linear PTO damping to the sea bed (N s/m) */
#define VR_F0 10u         /* inputs: the hydro FMU's linearised force F ~ F0 + F0_rate (t - t_n) + dF_dx x + dF_dv v */
#define VR_F0_RATE 11u
#define VR_DF_DX 12u
#define VR_DF_DV 13u
#define VR_X 20u          /* outputs: heave displacement (m) and velocity (m/s) */
#define VR_V 21u
#define VR_POWER 22u      /* output: power absorbed by the PTO, c v^2 (W) */
#define PARAMETER_RESOURCE "parameters.txt" /* the parameters' start values: mass A_inf c */
#define SUBSTEPS 10       /* trapezoidal sub-steps per communication step */

#endif
