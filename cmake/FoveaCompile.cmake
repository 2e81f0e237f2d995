# Warnings and sanitizers applied to every Fovea target through fovea_target_defaults().

set(_fovea_sanitize_flags "")
set(_fovea_sanitize_warnings "")
if(FOVEA_SANITIZE)
    if(FOVEA_SANITIZE MATCHES "thread" AND FOVEA_SANITIZE MATCHES "address")
        message(FATAL_ERROR "FOVEA_SANITIZE: thread cannot be combined with address")
    endif()
    set(_fovea_sanitize_flags -fsanitize=${FOVEA_SANITIZE} -fno-omit-frame-pointer -g1)
    if(FOVEA_SANITIZE MATCHES "undefined")
        list(APPEND _fovea_sanitize_flags -fno-sanitize-recover=undefined)
        # GCC leaves float-to-integer overflow out of "undefined" (Clang does not): without it a
        # cast of 1e300 to int64 passed the ASan tree and failed only the clang fuzz smoke.
        if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
            list(APPEND _fovea_sanitize_flags -fsanitize=float-cast-overflow
                 -fno-sanitize-recover=float-cast-overflow)
        endif()
    endif()
    # GCC's flow analysis under sanitizer instrumentation reports maybe-uninitialized inside
    # libstdc++ (std::function in <regex>), and -Wtsan says TSan cannot see
    # std::atomic_thread_fence, which the seqlock relies on; neither is about our code, so
    # under -Werror they stay warnings in sanitizer trees.
    list(APPEND _fovea_sanitize_warnings
        $<$<COMPILE_LANG_AND_ID:CXX,GNU>:-Wno-error=maybe-uninitialized>)
    if(FOVEA_SANITIZE MATCHES "thread")
        list(APPEND _fovea_sanitize_warnings $<$<COMPILE_LANG_AND_ID:CXX,GNU>:-Wno-tsan>)
    endif()
    # Sanitizers must see every translation unit, including third-party headers we instantiate.
    add_compile_options(${_fovea_sanitize_flags})
    add_link_options(${_fovea_sanitize_flags})
endif()

function(fovea_target_defaults target)
    target_compile_options(${target} PRIVATE
        $<$<COMPILE_LANG_AND_ID:CXX,GNU,Clang>:-Wall -Wextra -Wpedantic>
        $<$<COMPILE_LANG_AND_ID:CXX,GNU>:-Wshadow=local>
        $<$<COMPILE_LANG_AND_ID:C,GNU,Clang>:-Wall -Wextra -Wpedantic>)
    if(FOVEA_WERROR)
        target_compile_options(${target} PRIVATE -Werror ${_fovea_sanitize_warnings})
    endif()
endfunction()
