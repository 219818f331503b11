#pragma once
// rigidae's serial N_Vector: SUNDIALS' serial vector layout with operations
// compiled by rigidae.
//
// Debian's SUNDIALS libraries are built without optimisation, and a SUNDIALS
// integrator spends a third of its time in vector operations on vectors of 7
// to 20 entries. These vectors keep the serial content (length, own_data,
// data; NVECTOR_SERIAL's id), so SUNDIALS' dense and KLU modules and
// N_VGetArrayPointer accept them unchanged, but every arithmetic operation
// IDA, CVODE and ARKODE call is ours, and the fused and vector-array
// operations are enabled.
//
// Same arithmetic as NVECTOR_SERIAL 6.4: every entry is computed with the
// same expression in the same order (N_VLinearSum's special cases such as
// c (x + y) for a = b included; reductions summed in index order), so a run
// takes the same steps to the last bit. The fused operations give the
// entry-wise results of SUNDIALS' fallbacks (a scale, then x += c_i X_i in
// order). Build with -ffp-contract=off semantics (the project's default
// with -std=c++20 and no -mfma): a fused multiply-add would change
// roundings.
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>

namespace rigidae::sun {

// A new serial vector of length n with rigidae's operations (nullptr when
// out of memory). Clones keep the operations. Free with N_VDestroy.
N_Vector new_serial_vector(sunindextype n, SUNContext ctx);

// Replaces the arithmetic of an existing NVECTOR_SERIAL vector by rigidae's
// (and enables the fused operations). Returns v.
N_Vector use_rigidae_operations(N_Vector v);

}  // namespace rigidae::sun
