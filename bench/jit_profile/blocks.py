#!/usr/bin/env python3
"""Where llvmpipe's JIT code spends its instructions, block by block (bench/jit_profile.sh).

Reads one callgrind dump made with --dump-instr=yes and the code regions bench/jit_profile/exec_dump.c saved,
disassembles them with objdump, and prints
  - execution-count classes: all instructions executed the same number of times, i.e. one piece of the shader
    per class (per frame: the sample loop's body, the calls of a texture-sampling function, the per-ray code of
    a SIMD group, ...), largest total first;
  - with --blocks, the runs of consecutive instructions with equal counts in address order (the shader's
    layout: loops show as ranges whose last jump goes back), with their jumps and calls;
  - with --listing FILE, the whole annotated disassembly.

  blocks.py CALLGRIND_DUMP DUMP_DIR [--blocks] [--listing FILE]
"""
import collections
import os
import re
import subprocess
import sys


def instruction_costs(path):
    """Self cost (Ir) per instruction address, from a callgrind file written with --dump-instr=yes."""
    cost = collections.Counter()
    last = 0
    skip_call_line = False
    with open(path) as f:
        for line in f:
            if line.startswith('calls='):
                skip_call_line = True  # the next cost line is the call's inclusive cost
                continue
            if not line or line[0] not in '0123456789+-*':
                continue
            parts = line.split()
            pos = parts[0]
            if pos.startswith('0x'):
                addr = int(pos, 16)
            elif pos[0] == '+':
                addr = last + int(pos[1:], 0)
            elif pos[0] == '-':
                addr = last - int(pos[1:], 0)
            elif pos == '*':
                addr = last
            else:
                addr = int(pos, 0)
            last = addr
            if skip_call_line:
                skip_call_line = False
                continue
            if len(parts) > 2:  # positions: instr line, then Ir
                cost[addr] += int(parts[2])
    return cost


def disassemble(path, start):
    out = subprocess.run(['objdump', '-D', '-b', 'binary', '-mi386:x86-64', '--adjust-vma=%#x' % start, path],
                         capture_output=True, text=True, check=True).stdout
    for line in out.splitlines():
        m = re.match(r'\s*([0-9a-f]+):\t(?:[0-9a-f]{2} )+\s*\t?(.*)', line)
        if m:
            yield int(m.group(1), 16), m.group(2).strip()


def main(argv):
    if len(argv) < 3:
        sys.exit(__doc__)
    dump, regions_dir = argv[1], argv[2]
    show_blocks = '--blocks' in argv
    listing = argv[argv.index('--listing') + 1] if '--listing' in argv else None
    cost = instruction_costs(dump)
    rows = []  # (address, count, instruction) of the regions that ran
    for name in sorted(os.listdir(regions_dir)):
        m = re.match(r'([0-9a-f]+)_([0-9a-f]+)\.bin$', name)
        if not m:
            continue
        start, length = int(m.group(1), 16), int(m.group(2), 16)
        if not any(start <= a < start + length for a in cost):
            continue
        rows += [(a, cost.get(a, 0), ins) for a, ins in disassemble(os.path.join(regions_dir, name), start)]
    total = sum(c for _, c, _ in rows)
    if not total:
        sys.exit('blocks.py: no counted instruction in the dumped regions of ' + regions_dir)
    sizes = collections.Counter(c for _, c, _ in rows if c)  # instructions per execution count
    print('%d instructions in JIT code' % total)
    print('%10s %7s %12s %6s' % ('executed', 'instrs', 'total', 'share'))
    for c, n in sorted(sizes.items(), key=lambda item: -item[0] * item[1])[:20]:
        print('%10d %7d %12d %5.1f%%' % (c, n, c * n, 100.0 * c * n / total))
    if show_blocks:
        print('\nblocks in address order (count, instructions, last jumps and calls):')
        run = None
        for a, c, ins in rows + [(None, None, '')]:
            if c == 0:
                continue  # padding and never-run code
            if run and c == run[2]:
                run[1] = a
                run[3] += 1
                if ins.startswith(('j', 'call')):
                    run[4].append(ins)
                continue
            if run:
                print('%x-%x %10d x %4d  %s' % (run[0], run[1], run[2], run[3], ' | '.join(run[4][-3:])))
            run = [a, a, c, 1, [ins] if ins.startswith(('j', 'call')) else []] if a is not None else None
    if listing:
        with open(listing, 'w') as f:
            for a, c, ins in rows:
                f.write('%10d  %x  %s\n' % (c, a, ins))


if __name__ == '__main__':
    main(sys.argv)
