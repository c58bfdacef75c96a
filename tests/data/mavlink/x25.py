# CRC-16/MCRF4XX (X.25), as the MAVLink specification writes its checksum:
# shared by crc_extra.py and reference_frames.py (run by hand).
def crc_acc(b, crc):
    tmp = b ^ (crc & 0xff)
    tmp = (tmp ^ (tmp << 4)) & 0xff
    return ((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4)) & 0xffff


def crcs(bs, crc=0xffff):
    for b in bs:
        crc = crc_acc(b, crc)
    return crc
