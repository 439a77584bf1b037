# Flash and RAM use of a board from `avr-size -A NAME.elf`; fails when it would not fit.
# Flash holds .text and .data (the initial values); RAM holds .data, .bss and .noinit,
# and the stack needs what is left (STACK bytes at least).
$1 == ".text" || $1 == ".data" { flash += $2 }
$1 == ".data" || $1 == ".bss" || $1 == ".noinit" { ram += $2 }
END {
    printf "%s: flash %d of %d bytes (%.0f%%), RAM %d of %d bytes (%.0f%%)\n", \
        name, flash, fmax, 100 * flash / fmax, ram, rmax, 100 * ram / rmax
    if (flash > fmax) { printf "%s: does not fit: %d bytes of flash over\n", name, flash - fmax; exit 1 }
    if (ram > rmax - stack) {
        printf "%s: does not fit: %d bytes of RAM leave less than %d for the stack\n", name, ram, stack
        exit 1
    }
}
