/* FMI 2.0 co-simulation interface of the native FMUs: the FMI calls onto cosimulation.h (the model in model.c).
 *
 * Reals only (the hydro FMU has no other types); a step that cannot be taken returns fmi2Error with a logged reason
 * (never fmi2Discard: OMSimulator ends a run on Discard silently, with exit status 0); after it, the instance
 * accepts only getters, reset and free. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cosimulation.h"
#include "fmi2Functions.h"

static void host_log2(fmu_instance *instance, fmu_status status, const char *category, const char *message)
{
    fmi2CallbackLogger logger = (fmi2CallbackLogger)instance->host_logger;
    if (logger != NULL)
        logger(instance->host_environment, instance->name, (fmi2Status)status, category, "%s", message);
}

static fmu_instance *valid(fmi2Component c, const char *call, int allowed)
{
    fmu_instance *instance = (fmu_instance *)c;
    if (instance == NULL)
        return NULL;
    if (!(allowed & (1 << instance->phase))) {
        static const char *names[] = {"instantiated", "initialisation mode", "step mode", "terminated",
                                      "failed (a step was refused)"};
        fmu_log(instance, FMU_ERROR, "logError", "%s is not allowed when the FMU is %s", call,
                names[instance->phase]);
        return NULL;
    }
    return instance;
}

#define ANY ((1 << FMU_INSTANTIATED) | (1 << FMU_INITIALIZATION) | (1 << FMU_STEPPING) | (1 << FMU_TERMINATED) | \
             (1 << FMU_FAILED))
#define SETTABLE ((1 << FMU_INSTANTIATED) | (1 << FMU_INITIALIZATION) | (1 << FMU_STEPPING))

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    (void)nCategories;
    (void)categories;
    fmu_instance *instance = valid(c, "fmi2SetDebugLogging", ANY);
    if (instance == NULL)
        return fmi2Error;
    instance->logging_on = loggingOn ? 1 : 0;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    (void)visible;
    fmu_instance *instance = calloc(1, sizeof *instance);
    if (instance == NULL)
        return NULL;
    instance->fmi_version = 2;
    instance->log = host_log2;
    if (functions != NULL) {
        instance->host_logger = (void (*)(void))functions->logger;
        instance->host_environment = functions->componentEnvironment;
    }
    instance->logging_on = loggingOn ? 1 : 0;
    snprintf(instance->name, sizeof instance->name, "%s", instanceName != NULL ? instanceName : "");
    int ok = 1;
    if (fmuType != fmi2CoSimulation) {
        fmu_log(instance, FMU_ERROR, "logError", "this FMU supports co-simulation only");
        ok = 0;
    }
    ok = ok && fmu_set_resources(instance, fmuResourceLocation) == FMU_OK;
    fmu_clock_start(instance, 0.0);
    ok = ok && model_instantiate(instance) == FMU_OK;
    ok = ok && model_check_token(instance, fmuGUID) == FMU_OK;
    if (!ok) {
        model_free(instance);
        free(instance);
        return NULL;
    }
    instance->phase = FMU_INSTANTIATED;
    return instance;
}

void fmi2FreeInstance(fmi2Component c)
{
    fmu_instance *instance = (fmu_instance *)c;
    if (instance == NULL)
        return;
    model_free(instance);
    free(instance);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    fmu_instance *instance = valid(c, "fmi2SetupExperiment", 1 << FMU_INSTANTIATED);
    if (instance == NULL)
        return fmi2Error;
    fmu_clock_start(instance, startTime);
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    fmu_instance *instance = valid(c, "fmi2EnterInitializationMode", 1 << FMU_INSTANTIATED);
    if (instance == NULL)
        return fmi2Error;
    instance->phase = FMU_INITIALIZATION;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    fmu_instance *instance = valid(c, "fmi2ExitInitializationMode", 1 << FMU_INITIALIZATION);
    if (instance == NULL)
        return fmi2Error;
    if (model_exit_initialization(instance) != FMU_OK)
        return fmi2Error;
    instance->phase = FMU_STEPPING;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    fmu_instance *instance = valid(c, "fmi2Terminate", (1 << FMU_STEPPING) | (1 << FMU_FAILED));
    if (instance == NULL)
        return fmi2Error;
    instance->phase = FMU_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    fmu_instance *instance = valid(c, "fmi2Reset", ANY);
    if (instance == NULL)
        return fmi2Error;
    fmu_clock_start(instance, 0.0);
    if (model_reset(instance) != FMU_OK)
        return fmi2Error;
    instance->phase = FMU_INSTANTIATED;
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    fmu_instance *instance = valid(c, "fmi2GetReal", ANY);
    if (instance == NULL || (nvr > 0 && (vr == NULL || value == NULL)))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++)
        if (model_get_float64(instance, vr[i], &value[i]) != FMU_OK)
            return fmi2Error;
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    fmu_instance *instance = valid(c, "fmi2SetReal", SETTABLE);
    if (instance == NULL || (nvr > 0 && (vr == NULL || value == NULL)))
        return fmi2Error;
    for (size_t i = 0; i < nvr; i++)
        if (model_set_float64(instance, vr[i], value[i]) != FMU_OK)
            return fmi2Error;
    return fmi2OK;
}

static fmi2Status no_variables(fmi2Component c, const char *call, size_t nvr)
{
    fmu_instance *instance = valid(c, call, ANY);
    if (instance == NULL)
        return fmi2Error;
    if (nvr == 0)
        return fmi2OK;
    fmu_log(instance, FMU_ERROR, "logError", "%s: this FMU has only Real variables", call);
    return fmi2Error;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2GetInteger", nvr);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2GetBoolean", nvr);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2GetString", nvr);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2SetInteger", nvr);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2SetBoolean", nvr);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2SetString", nvr);
}

/* ---- FMU state ---- */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    fmu_instance *instance = valid(c, "fmi2GetFMUstate", SETTABLE | (1 << FMU_TERMINATED));
    if (instance == NULL || FMUstate == NULL)
        return fmi2Error;
    return model_state_get(instance, (void **)FMUstate) == FMU_OK ? fmi2OK : fmi2Error;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    fmu_instance *instance = valid(c, "fmi2SetFMUstate", ANY);
    if (instance == NULL || FMUstate == NULL)
        return fmi2Error;
    if (model_state_set(instance, FMUstate) != FMU_OK)
        return fmi2Error;
    if (instance->phase == FMU_FAILED || instance->phase == FMU_TERMINATED)
        instance->phase = FMU_STEPPING;
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    (void)c;
    if (FMUstate != NULL) {
        model_state_free(*FMUstate);
        *FMUstate = NULL;
    }
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    fmu_instance *instance = valid(c, "fmi2SerializedFMUstateSize", ANY);
    if (instance == NULL || size == NULL)
        return fmi2Error;
    return model_state_size(instance, FMUstate, size) == FMU_OK ? fmi2OK : fmi2Error;
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{
    fmu_instance *instance = valid(c, "fmi2SerializeFMUstate", ANY);
    if (instance == NULL || serializedState == NULL)
        return fmi2Error;
    return model_state_serialize(instance, FMUstate, (unsigned char *)serializedState, size) == FMU_OK ? fmi2OK
                                                                                                      : fmi2Error;
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    fmu_instance *instance = valid(c, "fmi2DeSerializeFMUstate", ANY);
    if (instance == NULL || serializedState == NULL || FMUstate == NULL)
        return fmi2Error;
    return model_state_deserialize(instance, (const unsigned char *)serializedState, size, (void **)FMUstate) ==
                   FMU_OK
               ? fmi2OK
               : fmi2Error;
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    fmu_instance *instance = valid(c, "fmi2GetDirectionalDerivative", ANY);
    if (instance == NULL || (nUnknown > 0 && (vUnknown_ref == NULL || dvUnknown == NULL)) ||
        (nKnown > 0 && (vKnown_ref == NULL || dvKnown == NULL)))
        return fmi2Error;
    for (size_t i = 0; i < nUnknown; i++) {
        double sum = 0.0;
        for (size_t j = 0; j < nKnown; j++) {
            double d = 0.0;
            if (model_partial(instance, vUnknown_ref[i], vKnown_ref[j], &d) != FMU_OK)
                return fmi2Error;
            sum += d * dvKnown[j];
        }
        dvUnknown[i] = sum;
    }
    return fmi2OK;
}

/* ---- Model exchange: not provided ---- */

static fmi2Status no_model_exchange(fmi2Component c, const char *call)
{
    fmu_log((fmu_instance *)c, FMU_ERROR, "logError", "%s: this FMU supports co-simulation only", call);
    return fmi2Error;
}

fmi2Status fmi2EnterEventMode(fmi2Component c) { return no_model_exchange(c, "fmi2EnterEventMode"); }

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    (void)info;
    return no_model_exchange(c, "fmi2NewDiscreteStates");
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return no_model_exchange(c, "fmi2EnterContinuousTimeMode"); }

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    (void)enterEventMode;
    (void)terminateSimulation;
    return no_model_exchange(c, "fmi2CompletedIntegratorStep");
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    (void)time;
    return no_model_exchange(c, "fmi2SetTime");
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    (void)x;
    (void)nx;
    return no_model_exchange(c, "fmi2SetContinuousStates");
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    (void)derivatives;
    (void)nx;
    return no_model_exchange(c, "fmi2GetDerivatives");
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
    (void)eventIndicators;
    (void)ni;
    return no_model_exchange(c, "fmi2GetEventIndicators");
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    (void)x;
    (void)nx;
    return no_model_exchange(c, "fmi2GetContinuousStates");
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    (void)x_nominal;
    (void)nx;
    return no_model_exchange(c, "fmi2GetNominalsOfContinuousStates");
}

/* ---- Co-simulation ---- */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    fmu_log((fmu_instance *)c, FMU_ERROR, "logError", "fmi2SetRealInputDerivatives: not supported "
            "(canInterpolateInputs is false)");
    return fmi2Error;
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    fmu_log((fmu_instance *)c, FMU_ERROR, "logError", "fmi2GetRealOutputDerivatives: not supported "
            "(maxOutputDerivativeOrder is 0; the linearised outputs F0_rate give the force's rate)");
    return fmi2Error;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    fmu_instance *instance = valid(c, "fmi2DoStep", 1 << FMU_STEPPING);
    if (instance == NULL)
        return fmi2Error;
    int take = 0;
    if (fmu_step_request(instance, currentCommunicationPoint, communicationStepSize, &take) != FMU_OK) {
        instance->phase = FMU_FAILED;
        return fmi2Error;
    }
    if (!take)
        return fmi2OK;
    if (model_do_step(instance, communicationStepSize) != FMU_OK) {
        instance->phase = FMU_FAILED;
        return fmi2Error;
    }
    fmu_clock_advance(instance, communicationStepSize);
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    fmu_log((fmu_instance *)c, FMU_ERROR, "logError", "fmi2CancelStep: steps are synchronous (canRunAsynchronuously "
            "is false)");
    return fmi2Error;
}

static fmi2Status no_status(fmi2Component c, const char *call)
{
    fmu_log((fmu_instance *)c, FMU_ERROR, "logError", "%s: steps are synchronous, there is no pending status", call);
    return fmi2Error;
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s;
    (void)value;
    return no_status(c, "fmi2GetStatus");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    fmu_instance *instance = (fmu_instance *)c;
    if (instance != NULL && s == fmi2LastSuccessfulTime && value != NULL) {
        *value = instance->time;
        return fmi2OK;
    }
    return no_status(c, "fmi2GetRealStatus");
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s;
    (void)value;
    return no_status(c, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    (void)s;
    (void)value;
    return no_status(c, "fmi2GetBooleanStatus");
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    (void)s;
    (void)value;
    return no_status(c, "fmi2GetStringStatus");
}
