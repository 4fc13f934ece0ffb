// Bindings and sizes of the timing calibration kernel
// (gpu/shaders/timing_calibration.comp, gpu/passes/timing_calibration.h);
// included by GLSL and C++.
#ifndef GI_TIMING_CALIBRATION_BINDINGS_H
#define GI_TIMING_CALIBRATION_BINDINGS_H

#define BINDING_CALIBRATION_TABLE 0
#define CALIBRATION_GROUP 64
// 256 KiB: past L1 and L2 of one core, within the last-level cache.
#define CALIBRATION_TABLE_WORDS 65536

#endif
