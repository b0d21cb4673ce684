# SPDX-License-Identifier: Apache-2.0
# Sourced by scripts/sanitize.sh and scripts/fuzz.sh: how the sanitizer runtimes behave.
#   halt_on_error / abort_on_error: the first report ends the program with a failure.
#   detect_leaks: LeakSanitizer at exit; sanitizer/lsan.supp lists the external leaks ignored, each
#                 with its reason.
#   strict_string_checks, detect_stack_use_after_return: the stricter ASan checks.
#   allocator_may_return_null: an impossible allocation fails as it does without ASan (OpenCV
#                 throws, operator new throws std::bad_alloc) instead of aborting; the tests that
#                 probe absurd sizes check that the library reports it.
here_env="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:allocator_may_return_null=1"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="suppressions=$here_env/sanitizer/lsan.supp:print_suppressions=0"
