// Constants shared by C++ and GLSL. Include from both; keep it to #defines so
// either language parses it.
#ifndef AAL_CONFIG_H
#define AAL_CONFIG_H

#define AAL_PI 3.14159265358979323846
#define AAL_TWO_PI 6.28318530717958647692

// Workgroup size of the cap parity compute shader.
#define AAL_CAPS_PARITY_GROUP_SIZE 64

#endif
