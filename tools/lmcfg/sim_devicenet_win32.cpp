// Windows: `lmcfg sim` is not in the Windows build (cmd_sim_win32.cpp), so
// neither are its DeviceNet options (sim_devicenet.cpp): this file replaces
// that one with nothing.
