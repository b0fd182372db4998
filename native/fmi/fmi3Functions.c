/* FMI 3.0 co-simulation interface of the native FMUs: the FMI calls onto cosimulation.h (the model in model.c).
 *
 * Float64 variables only, scalars and arrays (an array's value reference stands for consecutive scalar references
 * of the model: model_float64_elements); no event mode, no clocks. A step that cannot be taken returns fmi3Error
 * with a logged reason (never fmi3Discard); after it, the instance accepts only getters, reset and free. The
 * functions of model exchange, scheduled execution, clocks and the other types are present (every FMI 3.0 binary
 * exports them) and return fmi3Error with a message. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cosimulation.h"
#include "fmi3Functions.h"

#define VR_TIME 0u

static void host_log3(fmu_instance *instance, fmu_status status, const char *category, const char *message)
{
    fmi3LogMessageCallback logger = (fmi3LogMessageCallback)instance->host_logger;
    if (logger != NULL)
        logger(instance->host_environment, (fmi3Status)status, category, message);
}

static fmu_instance *valid(fmi3Instance c, const char *call, int allowed)
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

static fmi3Status unsupported(fmi3Instance c, const char *call)
{
    fmu_log((fmu_instance *)c, FMU_ERROR, "logError", "%s: not supported by this co-simulation FMU (Float64 "
            "variables, no event mode, no clocks)", call);
    return fmi3Error;
}

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    (void)nCategories;
    (void)categories;
    fmu_instance *instance = valid(c, "fmi3SetDebugLogging", ANY);
    if (instance == NULL)
        return fmi3Error;
    instance->logging_on = loggingOn ? 1 : 0;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)loggingOn;
    if (logMessage != NULL)
        logMessage(instanceEnvironment, fmi3Error, "logError", "this FMU supports co-simulation only");
    (void)instanceName;
    return NULL;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage,
                                               fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName;
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)loggingOn;
    (void)clockUpdate;
    (void)lockPreemption;
    (void)unlockPreemption;
    if (logMessage != NULL)
        logMessage(instanceEnvironment, fmi3Error, "logError", "this FMU supports co-simulation only");
    return NULL;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    (void)visible;
    (void)earlyReturnAllowed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    fmu_instance *instance = calloc(1, sizeof *instance);
    if (instance == NULL)
        return NULL;
    instance->fmi_version = 3;
    instance->log = host_log3;
    instance->host_logger = (void (*)(void))logMessage;
    instance->host_environment = instanceEnvironment;
    instance->logging_on = loggingOn ? 1 : 0;
    snprintf(instance->name, sizeof instance->name, "%s", instanceName != NULL ? instanceName : "");
    int ok = 1;
    if (eventModeUsed) {
        fmu_log(instance, FMU_ERROR, "logError", "this FMU has no event mode (hasEventMode is false)");
        ok = 0;
    }
    ok = ok && fmu_set_resources(instance, resourcePath) == FMU_OK;
    fmu_clock_start(instance, 0.0);
    ok = ok && model_instantiate(instance) == FMU_OK;
    ok = ok && model_check_token(instance, instantiationToken) == FMU_OK;
    if (!ok) {
        model_free(instance);
        free(instance);
        return NULL;
    }
    instance->phase = FMU_INSTANTIATED;
    return instance;
}

void fmi3FreeInstance(fmi3Instance c)
{
    fmu_instance *instance = (fmu_instance *)c;
    if (instance == NULL)
        return;
    model_free(instance);
    free(instance);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    fmu_instance *instance = valid(c, "fmi3EnterInitializationMode", 1 << FMU_INSTANTIATED);
    if (instance == NULL)
        return fmi3Error;
    fmu_clock_start(instance, startTime);
    instance->phase = FMU_INITIALIZATION;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance c)
{
    fmu_instance *instance = valid(c, "fmi3ExitInitializationMode", 1 << FMU_INITIALIZATION);
    if (instance == NULL)
        return fmi3Error;
    if (model_exit_initialization(instance) != FMU_OK)
        return fmi3Error;
    instance->phase = FMU_STEPPING;
    return fmi3OK;
}

fmi3Status fmi3EnterStepMode(fmi3Instance c)
{
    fmu_instance *instance = valid(c, "fmi3EnterStepMode", 1 << FMU_STEPPING);
    return instance == NULL ? fmi3Error : fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance c)
{
    fmu_instance *instance = valid(c, "fmi3Terminate", (1 << FMU_STEPPING) | (1 << FMU_FAILED));
    if (instance == NULL)
        return fmi3Error;
    instance->phase = FMU_TERMINATED;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance c)
{
    fmu_instance *instance = valid(c, "fmi3Reset", ANY);
    if (instance == NULL)
        return fmi3Error;
    fmu_clock_start(instance, 0.0);
    if (model_reset(instance) != FMU_OK)
        return fmi3Error;
    instance->phase = FMU_INSTANTIATED;
    return fmi3OK;
}

static fmu_status elements(fmu_instance *instance, fmi3ValueReference vr, uint32_t *first, size_t *count)
{
    if (vr == VR_TIME) {
        *first = VR_TIME;
        *count = 1;
        return FMU_OK;
    }
    return model_float64_elements(instance, vr, first, count);
}

fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                          fmi3Float64 values[], size_t nValues)
{
    fmu_instance *instance = valid(c, "fmi3GetFloat64", ANY);
    if (instance == NULL || (nValueReferences > 0 && (valueReferences == NULL || values == NULL)))
        return fmi3Error;
    size_t k = 0;
    for (size_t i = 0; i < nValueReferences; i++) {
        uint32_t first = 0;
        size_t count = 0;
        if (elements(instance, valueReferences[i], &first, &count) != FMU_OK)
            return fmi3Error;
        if (k + count > nValues) {
            fmu_log(instance, FMU_ERROR, "logError", "fmi3GetFloat64: %zu values asked for, the variables have more",
                    nValues);
            return fmi3Error;
        }
        for (size_t j = 0; j < count; j++, k++) {
            if (first == VR_TIME)
                values[k] = instance->time;
            else if (model_get_float64(instance, first + (uint32_t)j, &values[k]) != FMU_OK)
                return fmi3Error;
        }
    }
    if (k != nValues) {
        fmu_log(instance, FMU_ERROR, "logError", "fmi3GetFloat64: %zu values asked for, the variables have %zu",
                nValues, k);
        return fmi3Error;
    }
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                          const fmi3Float64 values[], size_t nValues)
{
    fmu_instance *instance = valid(c, "fmi3SetFloat64", SETTABLE);
    if (instance == NULL || (nValueReferences > 0 && (valueReferences == NULL || values == NULL)))
        return fmi3Error;
    size_t k = 0;
    for (size_t i = 0; i < nValueReferences; i++) {
        uint32_t first = 0;
        size_t count = 0;
        if (elements(instance, valueReferences[i], &first, &count) != FMU_OK)
            return fmi3Error;
        if (k + count > nValues || first == VR_TIME) {
            fmu_log(instance, FMU_ERROR, "logError", "fmi3SetFloat64: %s", first == VR_TIME ? "time is not settable"
                    : "fewer values than the variables have");
            return fmi3Error;
        }
        for (size_t j = 0; j < count; j++, k++)
            if (model_set_float64(instance, first + (uint32_t)j, values[k]) != FMU_OK)
                return fmi3Error;
    }
    if (k != nValues) {
        fmu_log(instance, FMU_ERROR, "logError", "fmi3SetFloat64: %zu values given, the variables have %zu", nValues,
                k);
        return fmi3Error;
    }
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance c, fmi3ValueReference valueReference,
                                               size_t *nDependencies)
{
    (void)valueReference;
    (void)nDependencies;
    return unsupported(c, "fmi3GetNumberOfVariableDependencies (the dependencies are in the model description)");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance c, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies)
{
    (void)dependent;
    (void)elementIndicesOfDependent;
    (void)independents;
    (void)elementIndicesOfIndependents;
    (void)dependencyKinds;
    (void)nDependencies;
    return unsupported(c, "fmi3GetVariableDependencies (the dependencies are in the model description)");
}

/* ---- FMU state ---- */

fmi3Status fmi3GetFMUState(fmi3Instance c, fmi3FMUState *FMUState)
{
    fmu_instance *instance = valid(c, "fmi3GetFMUState", SETTABLE | (1 << FMU_TERMINATED));
    if (instance == NULL || FMUState == NULL)
        return fmi3Error;
    return model_state_get(instance, (void **)FMUState) == FMU_OK ? fmi3OK : fmi3Error;
}

fmi3Status fmi3SetFMUState(fmi3Instance c, fmi3FMUState FMUState)
{
    fmu_instance *instance = valid(c, "fmi3SetFMUState", ANY);
    if (instance == NULL || FMUState == NULL)
        return fmi3Error;
    if (model_state_set(instance, FMUState) != FMU_OK)
        return fmi3Error;
    if (instance->phase == FMU_FAILED || instance->phase == FMU_TERMINATED)
        instance->phase = FMU_STEPPING;
    return fmi3OK;
}

fmi3Status fmi3FreeFMUState(fmi3Instance c, fmi3FMUState *FMUState)
{
    (void)c;
    if (FMUState != NULL) {
        model_state_free(*FMUState);
        *FMUState = NULL;
    }
    return fmi3OK;
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance c, fmi3FMUState FMUState, size_t *size)
{
    fmu_instance *instance = valid(c, "fmi3SerializedFMUStateSize", ANY);
    if (instance == NULL || size == NULL)
        return fmi3Error;
    return model_state_size(instance, FMUState, size) == FMU_OK ? fmi3OK : fmi3Error;
}

fmi3Status fmi3SerializeFMUState(fmi3Instance c, fmi3FMUState FMUState, fmi3Byte serializedState[], size_t size)
{
    fmu_instance *instance = valid(c, "fmi3SerializeFMUState", ANY);
    if (instance == NULL || serializedState == NULL)
        return fmi3Error;
    return model_state_serialize(instance, FMUState, serializedState, size) == FMU_OK ? fmi3OK : fmi3Error;
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance c, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState)
{
    fmu_instance *instance = valid(c, "fmi3DeserializeFMUState", ANY);
    if (instance == NULL || serializedState == NULL || FMUState == NULL)
        return fmi3Error;
    return model_state_deserialize(instance, serializedState, size, (void **)FMUState) == FMU_OK ? fmi3OK
                                                                                                 : fmi3Error;
}

/* ---- Directional derivatives: the total force F with respect to x and v ---- */

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance c, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    fmu_instance *instance = valid(c, "fmi3GetDirectionalDerivative", ANY);
    if (instance == NULL || (nUnknowns > 0 && (unknowns == NULL || sensitivity == NULL)) ||
        (nKnowns > 0 && (knowns == NULL || seed == NULL)))
        return fmi3Error;
    size_t out = 0;
    for (size_t i = 0; i < nUnknowns; i++) {
        uint32_t ufirst = 0;
        size_t ucount = 0;
        if (elements(instance, unknowns[i], &ufirst, &ucount) != FMU_OK)
            return fmi3Error;
        for (size_t a = 0; a < ucount; a++, out++) {
            if (out >= nSensitivity)
                break;
            double sum = 0.0;
            size_t in = 0;
            for (size_t j = 0; j < nKnowns; j++) {
                uint32_t kfirst = 0;
                size_t kcount = 0;
                if (elements(instance, knowns[j], &kfirst, &kcount) != FMU_OK)
                    return fmi3Error;
                for (size_t b = 0; b < kcount; b++, in++) {
                    double d = 0.0;
                    if (in >= nSeed || model_partial(instance, ufirst + (uint32_t)a, kfirst + (uint32_t)b, &d) !=
                                           FMU_OK)
                        return in >= nSeed ? unsupported(c, "fmi3GetDirectionalDerivative: seed too short")
                                           : fmi3Error;
                    sum += d * seed[in];
                }
            }
            sensitivity[out] = sum;
        }
    }
    if (out != nSensitivity) {
        fmu_log(instance, FMU_ERROR, "logError", "fmi3GetDirectionalDerivative: nSensitivity %zu, the unknowns have "
                "%zu elements", nSensitivity, out);
        return fmi3Error;
    }
    return fmi3OK;
}

/* ---- Co-simulation ---- */

fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean *eventHandlingNeeded,
                      fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    if (eventHandlingNeeded != NULL)
        *eventHandlingNeeded = fmi3False;
    if (terminateSimulation != NULL)
        *terminateSimulation = fmi3False;
    if (earlyReturn != NULL)
        *earlyReturn = fmi3False;
    fmu_instance *instance = valid(c, "fmi3DoStep", 1 << FMU_STEPPING);
    if (instance == NULL)
        return fmi3Error;
    int take = 0;
    fmu_status status = fmu_step_request(instance, currentCommunicationPoint, communicationStepSize, &take);
    if (status == FMU_OK && take) {
        status = model_do_step(instance, communicationStepSize);
        if (status == FMU_OK)
            fmu_clock_advance(instance, communicationStepSize);
    }
    if (lastSuccessfulTime != NULL)
        *lastSuccessfulTime = take ? instance->time : currentCommunicationPoint + communicationStepSize;
    if (status != FMU_OK) {
        instance->phase = FMU_FAILED;
        if (lastSuccessfulTime != NULL)
            *lastSuccessfulTime = instance->time;
        return fmi3Error;
    }
    return fmi3OK;
}

/* ---- Not supported (present because every FMI 3.0 binary exports them) ---- */

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterEventMode");
}

fmi3Status fmi3GetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float32 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetFloat32");
}

fmi3Status fmi3GetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int8 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetInt8");
}

fmi3Status fmi3GetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt8 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetUInt8");
}

fmi3Status fmi3GetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int16 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetInt16");
}

fmi3Status fmi3GetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt16 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetUInt16");
}

fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int32 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetInt32");
}

fmi3Status fmi3GetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt32 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetUInt32");
}

fmi3Status fmi3GetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Int64 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetInt64");
}

fmi3Status fmi3GetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetUInt64");
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Boolean values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetBoolean");
}

fmi3Status fmi3GetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3String values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetString");
}

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)valueSizes;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetBinary");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Clock values[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    return unsupported(instance, "fmi3GetClock");
}

fmi3Status fmi3SetFloat32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float32 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetFloat32");
}

fmi3Status fmi3SetInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int8 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetInt8");
}

fmi3Status fmi3SetUInt8(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt8 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetUInt8");
}

fmi3Status fmi3SetInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int16 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetInt16");
}

fmi3Status fmi3SetUInt16(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt16 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetUInt16");
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int32 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetInt32");
}

fmi3Status fmi3SetUInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt32 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetUInt32");
}

fmi3Status fmi3SetInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int64 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetInt64");
}

fmi3Status fmi3SetUInt64(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetUInt64");
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Boolean values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetBoolean");
}

fmi3Status fmi3SetString(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3String values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetString");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)valueSizes;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3SetBinary");
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Clock values[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)values;
    return unsupported(instance, "fmi3SetClock");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns, const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[], size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns;
    (void)nUnknowns;
    (void)knowns;
    (void)nKnowns;
    (void)seed;
    (void)nSeed;
    (void)sensitivity;
    (void)nSensitivity;
    return unsupported(instance, "fmi3GetAdjointDerivative");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterConfigurationMode");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3ExitConfigurationMode");
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)intervals;
    (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalDecimal");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalFraction");
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3Float64 shifts[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)shifts;
    return unsupported(instance, "fmi3GetShiftDecimal");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3GetShiftFraction");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float64 intervals[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)intervals;
    return unsupported(instance, "fmi3SetIntervalDecimal");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3SetIntervalFraction");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Float64 shifts[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)shifts;
    return unsupported(instance, "fmi3SetShiftDecimal");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EvaluateDiscreteStates");
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean* discreteStatesNeedUpdate, fmi3Boolean* terminateSimulation, fmi3Boolean* nominalsOfContinuousStatesChanged, fmi3Boolean* valuesOfContinuousStatesChanged, fmi3Boolean* nextEventTimeDefined, fmi3Float64* nextEventTime)
{
    (void)discreteStatesNeedUpdate;
    (void)terminateSimulation;
    (void)nominalsOfContinuousStatesChanged;
    (void)valuesOfContinuousStatesChanged;
    (void)nextEventTimeDefined;
    (void)nextEventTime;
    return unsupported(instance, "fmi3UpdateDiscreteStates");
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterContinuousTimeMode");
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean* enterEventMode, fmi3Boolean* terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    (void)enterEventMode;
    (void)terminateSimulation;
    return unsupported(instance, "fmi3CompletedIntegratorStep");
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    (void)time;
    return unsupported(instance, "fmi3SetTime");
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    (void)continuousStates;
    (void)nContinuousStates;
    return unsupported(instance, "fmi3SetContinuousStates");
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t nContinuousStates)
{
    (void)derivatives;
    (void)nContinuousStates;
    return unsupported(instance, "fmi3GetContinuousStateDerivatives");
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{
    (void)eventIndicators;
    (void)nEventIndicators;
    return unsupported(instance, "fmi3GetEventIndicators");
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    (void)continuousStates;
    (void)nContinuousStates;
    return unsupported(instance, "fmi3GetContinuousStates");
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nContinuousStates)
{
    (void)nominals;
    (void)nContinuousStates;
    return unsupported(instance, "fmi3GetNominalsOfContinuousStates");
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t* nEventIndicators)
{
    (void)nEventIndicators;
    return unsupported(instance, "fmi3GetNumberOfEventIndicators");
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t* nContinuousStates)
{
    (void)nContinuousStates;
    return unsupported(instance, "fmi3GetNumberOfContinuousStates");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues)
{
    (void)valueReferences;
    (void)nValueReferences;
    (void)orders;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetOutputDerivatives");
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference, fmi3Float64 activationTime)
{
    (void)clockReference;
    (void)activationTime;
    return unsupported(instance, "fmi3ActivateModelPartition");
}
