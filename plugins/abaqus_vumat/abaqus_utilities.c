/*
 * abaqus_utilities.c — the guarded call of a user subroutine (VUMAT or UMAT) and the Abaqus
 * utility routines it may call to report errors:
 *
 *   CALL XPLB_ABQERR(LOP, STRING, INTV, REALV, CHARV)   (Abaqus/Explicit)
 *   CALL STDB_ABQERR(LOP, STRING, INTV, REALV, CHARV)   (Abaqus/Standard)
 *     STRING with %I, %R, %S replaced by the next entries of INTV, REALV, CHARV
 *     (CHARACTER*8); LOP = 1 information and -1 warning (printed on stderr), -2 error (the
 *     block fails after the subroutine returns), -3 error that stops at once;
 *   CALL XPLB_EXIT, CALL XIT
 *     stops at once.
 *
 * and Fortran's STOP and ERROR STOP, which would otherwise end the whole musclefem process
 * (with status 0 for STOP): the gfortran runtime's entry points for them are defined here,
 * hidden, so that the linker binds the subroutine's STOP statements to these instead of
 * libgfortran's (the signatures of libgfortran 5, gfortran 8 and later). Outside a
 * call they exit as the runtime would.
 *
 * "At once" is a longjmp from the utility back to abaqus_call_guarded, across the subroutine's
 * Fortran frames (which hold no C++ objects; memory the subroutine ALLOCATEd on the way is not
 * freed). The jump never leaves the plugin: update() returns an error code to the host.
 * The context is thread-local, since the host calls update() from several threads.
 */
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "musclefem_vumat.h"

static _Thread_local AbaqusCall* current_call = NULL;

int abaqus_call_guarded(AbaqusCall* call, const char* routine, void (*body)(const void*),
                        const void* arguments) {
    call->routine = routine;
    call->failed = 0;
    call->message[0] = '\0';
    AbaqusCall* previous = current_call;
    current_call = call;
    if (setjmp(call->jump) == 0) body(arguments);
    current_call = previous;
    return call->failed;
}

/* Length of a blank-padded Fortran string without its trailing blanks. */
static size_t trimmed_length(const char* text, size_t length) {
    while (length > 0 && (text[length - 1] == ' ' || text[length - 1] == '\0')) --length;
    return length;
}

/* STRING with its %I, %R and %S replaced, cut to fit `capacity`. */
static void format_message(const char* string, size_t string_length, const int* intv,
                           const double* realv, const char* charv, size_t charv_length,
                           char* out, size_t capacity) {
    size_t used = 0, n = trimmed_length(string, string_length);
    int next_int = 0, next_real = 0, next_char = 0;
    out[0] = '\0';
    for (size_t i = 0; i < n && used + 1 < capacity; ++i) {
        char piece[64];
        const char* text = piece;
        size_t length = 0;
        char code = (i + 1 < n && string[i] == '%') ? string[i + 1] : '\0';
        if (code == 'I' || code == 'i') {
            length = (size_t)snprintf(piece, sizeof piece, "%d", intv[next_int++]);
            ++i;
        } else if (code == 'R' || code == 'r') {
            length = (size_t)snprintf(piece, sizeof piece, "%.9g", realv[next_real++]);
            ++i;
        } else if (code == 'S' || code == 's') {
            text = charv + charv_length * (size_t)next_char++;
            length = trimmed_length(text, charv_length);
            ++i;
        } else {
            piece[0] = string[i];
            length = 1;
        }
        if (length > capacity - 1 - used) length = capacity - 1 - used;
        memcpy(out + used, text, length);
        used += length;
        out[used] = '\0';
    }
}

/* XPLB_ABQERR and STDB_ABQERR (`utility` names which). */
static void abqerr(const char* utility, const int* lop, const char* string, const int* intv,
                   const double* realv, const char* charv, size_t string_length,
                   size_t charv_length) {
    char text[480];
    format_message(string, string_length, intv, realv, charv, charv_length, text, sizeof text);
    AbaqusCall* call = current_call;
    if (*lop >= 0 || *lop == -1 || call == NULL) {
        fprintf(stderr, "%s %s: %s\n", call == NULL ? "Abaqus routine" : call->routine,
                *lop >= 0 ? "info" : (*lop == -1 ? "warning" : "error"), text);
        return;
    }
    if (!call->failed) {
        snprintf(call->message, sizeof call->message, "%s (lop = %d): %s", utility, *lop, text);
        call->failed = 1;
    }
    if (*lop <= -3) longjmp(call->jump, 1);
}

void xplb_abqerr_(const int* lop, const char* string, const int* intv, const double* realv,
                  const char* charv, size_t string_length, size_t charv_length) {
    abqerr("XPLB_ABQERR", lop, string, intv, realv, charv, string_length, charv_length);
}

void stdb_abqerr_(const int* lop, const char* string, const int* intv, const double* realv,
                  const char* charv, size_t string_length, size_t charv_length) {
    abqerr("STDB_ABQERR", lop, string, intv, realv, charv, string_length, charv_length);
}

/* XPLB_EXIT and XIT: stop at once. */
static void exit_routine(const char* utility) {
    AbaqusCall* call = current_call;
    if (call == NULL) return;
    if (!call->failed) {
        snprintf(call->message, sizeof call->message, "the %s called %s", call->routine, utility);
        call->failed = 1;
    }
    longjmp(call->jump, 1);
}

void xplb_exit_(void) { exit_routine("XPLB_EXIT"); }

void xit_(void) { exit_routine("XIT"); }

/* Record `text` as the call's error and jump back, or exit with `status` outside a call. */
static void stop(int status, const char* what, const char* text, size_t length) {
    AbaqusCall* call = current_call;
    length = trimmed_length(text == NULL ? "" : text, text == NULL ? 0 : length);
    if (call == NULL) {
        fprintf(stderr, "%s %.*s\n", what, (int)length, text == NULL ? "" : text);
        exit(status);
    }
    if (!call->failed) {
        snprintf(call->message, sizeof call->message, "the %s executed %s%s%.*s", call->routine, what,
                 length > 0 ? " " : "", (int)length, text == NULL ? "" : text);
        call->failed = 1;
    }
    longjmp(call->jump, 1);
}

void _gfortran_stop_string(const char* text, size_t length, bool quiet) {
    (void)quiet;
    stop(0, "STOP", text, length);
}

void _gfortran_error_stop_string(const char* text, size_t length, bool quiet) {
    (void)quiet;
    stop(1, "ERROR STOP", text, length);
}

void _gfortran_stop_numeric(int code, bool quiet) {
    (void)quiet;
    char text[16];
    snprintf(text, sizeof text, "%d", code);
    stop(code, "STOP", text, strlen(text));
}

void _gfortran_error_stop_numeric(int code, bool quiet) {
    (void)quiet;
    char text[16];
    snprintf(text, sizeof text, "%d", code);
    stop(code, "ERROR STOP", text, strlen(text));
}
