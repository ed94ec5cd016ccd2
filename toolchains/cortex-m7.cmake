# The CPU: Arm Cortex-M7 with the double-precision FPU (FPv5-D16), hard-float ABI.
include(${CMAKE_CURRENT_LIST_DIR}/arm-none-eabi.cmake)
set(CMAKE_SYSTEM_PROCESSOR cortex-m7)

set(ITP_CPU_FLAGS "-mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard")
set(CMAKE_C_FLAGS_INIT "${ITP_CPU_FLAGS} ${ITP_COMMON_TARGET_FLAGS}")
set(CMAKE_CXX_FLAGS_INIT "${ITP_CPU_FLAGS} ${ITP_COMMON_TARGET_FLAGS}")
set(CMAKE_ASM_FLAGS_INIT "${ITP_CPU_FLAGS}")
set(CMAKE_EXE_LINKER_FLAGS_INIT "${ITP_CPU_FLAGS} --specs=nano.specs -nostartfiles -Wl,--gc-sections")
