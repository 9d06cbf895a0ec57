# Sourced by bench/shader_instructions.sh and bench/jit_profile.sh: how both run `ropecast` under callgrind so
# that it writes one dump per frame (--dump-after the renderers' per-frame functions, which wait for the GL timer
# and so for the frame's rasterization: LP_NUM_THREADS=0 rasterizes in the calling thread). The Mesa shader
# cache is off (shaders compile under the count), and valgrind schedules threads fairly (without it the loader
# thread starved and nothing was drawn).
# shellcheck shell=bash
export EGL_PLATFORM=${EGL_PLATFORM:-surfaceless} LP_NUM_THREADS=0 MESA_SHADER_CACHE_DISABLE=true
# shellcheck disable=SC2034  # used by the scripts that source this file
CALLGRIND_PER_FRAME=(valgrind --tool=callgrind --fair-sched=yes
                     --dump-after='ropecast::FrameRenderer::render(*' --dump-after='ropecast::BruteForcePass::render(*')
