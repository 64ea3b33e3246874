// Test bench for obb_core: frames of a scene back to back, for Verilator (--binary), Icarus
// and the gate-level netlist alike. Written by hand; `obbcd cosim` compiles it with the
// emitted core.
//
// Plusargs:
//   +stim=FILE    per frame a line `UPDATE N` (decimal: frame_update, the boxes), then the N
//                 boxes, one hex word per line (README.md, "File formats", has the layout)
//   +frames=F     how many frames FILE holds
//   +out=FILE     written, per frame: one line `pair A B` per pair taken from the stream, in
//                 order, then `done CLOCKS CYCLES CANDIDATES SAT_TESTS PAIRS CAPACITY_EXCEEDED
//                 PAIR_OVERFLOW`; before it, `abort` where +abort aborted the frame
//   +abort=C      abort each frame once, at its clock C (1 or more; default 0: never) if it has
//                 not finished: frame_start again, and the frame's boxes again from its first
//                 (pairs taken before the `abort` line are the aborted frame's; CLOCKS then
//                 counts from the abort)
//   +ready=K      pair_ready is high one clock in K (default 1: always), to throttle the stream
//   +timeout=T    give up (exit code non-zero) after T clocks without `done` (default 2^40)
//   +progress=P   print `progress CLOCK` every P clocks (default 0: never)
//   +waves=FILE   record waves (Verilator: build with --trace or --trace-fst; Icarus: vvp -fst
//                 for FST), from clock +waves_from=A (default 0) of the whole run; with
//                 +waves_to=B the run ends at clock B (Verilator ignores $dumpoff), and such a
//                 run's result is not complete; +waves_depth=D levels of hierarchy (Icarus;
//                 with Verilator the build takes --trace-depth)
`timescale 1ns/1ps
module tb;
  localparam CENTER = 23, HALF = 17, ROT = 18, GROUP = 3, INDEX = 20, COUNT = 40;
  localparam WORD = 3 * CENTER + 3 * HALF + 9 * ROT + GROUP;

  reg clock = 1'b0;
  always #2 clock = ~clock;

  // Inputs, changed only just after a rising edge (nonblocking), so the core samples them
  // cleanly on the next one.
  reg frame_start = 1'b0;
  reg frame_update = 1'b0;
  reg obb_valid = 1'b0;
  reg obb_last = 1'b0;
  reg pair_ready = 1'b0;
  reg [WORD-1:0] word = {WORD{1'b0}};

  wire obb_ready, pair_valid, done, busy, capacity_exceeded, pair_overflow;
  wire [INDEX-1:0] pair_a, pair_b;
  wire [COUNT-1:0] cycles, visits, sat_tests, pairs;

  obb_core dut (
    .clock(clock),
    .frame_start(frame_start), .frame_update(frame_update),
    .obb_valid(obb_valid), .obb_ready(obb_ready), .obb_last(obb_last),
    .obb_center$0(word[0*CENTER +: CENTER]),
    .obb_center$1(word[1*CENTER +: CENTER]),
    .obb_center$2(word[2*CENTER +: CENTER]),
    .obb_half$0(word[3*CENTER + 0*HALF +: HALF]),
    .obb_half$1(word[3*CENTER + 1*HALF +: HALF]),
    .obb_half$2(word[3*CENTER + 2*HALF +: HALF]),
    .obb_axes$0(word[3*CENTER + 3*HALF + 0*ROT +: ROT]),
    .obb_axes$1(word[3*CENTER + 3*HALF + 1*ROT +: ROT]),
    .obb_axes$2(word[3*CENTER + 3*HALF + 2*ROT +: ROT]),
    .obb_axes$3(word[3*CENTER + 3*HALF + 3*ROT +: ROT]),
    .obb_axes$4(word[3*CENTER + 3*HALF + 4*ROT +: ROT]),
    .obb_axes$5(word[3*CENTER + 3*HALF + 5*ROT +: ROT]),
    .obb_axes$6(word[3*CENTER + 3*HALF + 6*ROT +: ROT]),
    .obb_axes$7(word[3*CENTER + 3*HALF + 7*ROT +: ROT]),
    .obb_axes$8(word[3*CENTER + 3*HALF + 8*ROT +: ROT]),
    .obb_group(word[3*CENTER + 3*HALF + 9*ROT +: GROUP]),
    .pair_valid(pair_valid), .pair_ready(pair_ready),
    .pair_a(pair_a), .pair_b(pair_b),
    .done(done), .busy(busy), .capacity_exceeded(capacity_exceeded),
    .pair_overflow(pair_overflow),
    .cycles(cycles), .visits(visits), .sat_tests(sat_tests), .pairs(pairs)
  );

  reg [WORD-1:0] read_word;
  reg [1023:0] stim_name, out_name, waves_name;
  integer stim, out, boxes, ready_every, progress, sent, scanned, frames, frame, update;
  integer waves_depth, frame_at, sought;
  reg [63:0] clocks, timeout, waves_from, waves_to, abort_at;
  reg [63:0] run_clock = 64'd0;
  reg started, waves, aborted;

  // Clock 0 of a frame: its header, then frame_start (with frame_update); the first box (or the
  // empty frame's marker) follows.
  task start_frame;
    begin
      frame_at = $ftell(stim);
      scanned = $fscanf(stim, "%d %d\n", update, boxes);
      if (scanned != 2) begin
        $display("error: %0s has no header for frame %0d of %0d", stim_name, frame, frames);
        $fatal(1);
      end
      sent = 0;
      clocks <= 0;
      frame_start <= 1'b1;
      frame_update <= update != 0;
    end
  endtask

  // Puts the next box on the inputs from the next clock on (the read is blocking, the
  // assignment not, so that the core never sees a box early); a short file is an error, not a
  // silent short frame.
  task next_box;
    begin
      scanned = $fscanf(stim, "%h\n", read_word);
      if (scanned != 1) begin
        $display("error: %0s ends after %0d of %0d boxes", stim_name, sent, boxes);
        $fatal(1);
      end
      word <= read_word;
    end
  endtask

  initial begin
    if (!$value$plusargs("stim=%s", stim_name)) begin $display("error: no +stim"); $fatal(1); end
    if (!$value$plusargs("out=%s", out_name)) begin $display("error: no +out"); $fatal(1); end
    if (!$value$plusargs("frames=%d", frames)) begin $display("error: no +frames"); $fatal(1); end
    if (!$value$plusargs("ready=%d", ready_every)) ready_every = 1;
    if (!$value$plusargs("progress=%d", progress)) progress = 0;
    if (!$value$plusargs("timeout=%d", timeout)) timeout = 64'd1 << 40;
    if (!$value$plusargs("abort=%d", abort_at)) abort_at = 0;
    // The file is opened here, the dump starts at the window's first clock.
    waves = $value$plusargs("waves=%s", waves_name);
    if (waves) $dumpfile(waves_name);
    if (!$value$plusargs("waves_from=%d", waves_from)) waves_from = 0;
    if (!$value$plusargs("waves_to=%d", waves_to)) waves_to = 0;
    if (!$value$plusargs("waves_depth=%d", waves_depth)) waves_depth = 0;
    if (ready_every < 1) begin $display("error: +ready must be at least 1"); $fatal(1); end
    stim = $fopen(stim_name, "r");
    if (stim == 0) begin $display("error: cannot read %0s", stim_name); $fatal(1); end
    out = $fopen(out_name, "w");
    if (out == 0) begin $display("error: cannot write %0s", out_name); $fatal(1); end
    sent = 0;
    clocks = 0;
    frame = 0;
    started = 1'b0;
    aborted = 1'b0;
  end

  always @(posedge clock) begin
    run_clock <= run_clock + 1;
    if (waves && run_clock == waves_from) $dumpvars(waves_depth, tb);
    if (waves && waves_to != 0 && run_clock == waves_to) $finish;
    if (!started) begin
      started <= 1'b1;
      start_frame;
    end else begin
      frame_start <= 1'b0;
      clocks <= clocks + 1;
      // The box stream: the current box moves when the core takes it. The end marker alone
      // stays up until the next frame (the core reads it only while it loads, which after an
      // abort is some clocks later).
      if (clocks == 0) begin
        if (boxes == 0) begin
          obb_last <= 1'b1;
        end else begin
          next_box;
          obb_valid <= 1'b1;
          obb_last <= boxes == 1;
        end
      end else if (obb_valid && obb_ready) begin
        sent = sent + 1;
        if (sent == boxes) begin
          obb_valid <= 1'b0;
          obb_last <= 1'b0;
        end else begin
          next_box;
          obb_last <= sent + 1 == boxes;
        end
      end
      // The pair stream: a pair moves on a clock where valid and ready are both high.
      if (pair_valid && pair_ready) $fwrite(out, "pair %0d %0d\n", pair_a, pair_b);
      pair_ready <= (clocks + 1) % ready_every == 0;
      if (progress != 0 && clocks % progress == 0) $display("progress %0d", clocks);
      if (done && clocks > 1) begin
        $fwrite(out, "done %0d %0d %0d %0d %0d %0d %0d\n", clocks, cycles, visits, sat_tests,
                pairs, capacity_exceeded, pair_overflow);
        frame = frame + 1;
        aborted = 1'b0;
        if (frame == frames) begin
          $fclose(out);
          $finish;
        end else begin
          // The next frame at once: its frame_start on the clock after the first with done,
          // no idle clock between the frames. ($finish ends the run only after this clock.)
          start_frame;
        end
      end
      // The abort: the frame's header and boxes again, from the next clock.
      if (abort_at != 0 && !aborted && !done && clocks == abort_at) begin
        $fwrite(out, "abort\n");
        sought = $fseek(stim, frame_at, 0);
        if (sought != 0) begin $display("error: cannot seek in %0s", stim_name); $fatal(1); end
        aborted = 1'b1;
        start_frame;
      end
      if (clocks >= timeout) begin
        $display("error: no done after %0d clocks", clocks);
        $fatal(1);
      end
    end
  end
endmodule
