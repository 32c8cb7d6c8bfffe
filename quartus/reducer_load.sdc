# 150 MHz target (6.667 ns); change the period to explore. Inputs and outputs are virtual pins.
create_clock -name clock -period 6.667 [get_ports clock]
derive_clock_uncertainty
