# Reference frames for tests/unit/test_mavlink.cpp and the seeds of
# fuzz/corpus/fuzz_mavlink, made apart from the C++ code: Python's struct
# and hashlib, the CRC written out from the MAVLink spec. Run by hand:
#   python3 reference_frames.py
import struct, hashlib
from x25 import crc_acc, crcs
def frame(seq,sysid,compid,msgid,payload,extra,key=None,link=0,ts=0):
    p=payload.rstrip(b'\0') or payload[:1]
    inc=1 if key else 0
    hdr=bytes([0xFD,len(p),inc,0,seq,sysid,compid])+struct.pack('<I',msgid)[:3]
    c=crcs(hdr[1:]+p); c=crc_acc(extra,c)
    f=hdr+p+struct.pack('<H',c)
    if key:
        lt=bytes([link])+struct.pack('<Q',ts)[:6]
        f+=lt+hashlib.sha256(key+f+lt).digest()[:6]
    return f
def show(n,f): print(n, ', '.join('0x%02X'%b for b in f))
print('check 123456789', hex(crcs(b'123456789')))
hb=struct.pack('<IBBBBB',0,2,8,0,4,3)
show('heartbeat',frame(0,1,1,0,hb,50))
gp=struct.pack('<IiiiihhhH',1000,10000000,-20000000,130000,30000,150,-250,0,0)
show('gpi',frame(7,3,1,33,gp,104))
key=bytes(range(32))
cl=struct.pack('<7fHBBB',0,0,0,0,0,0,0,193,251,1,0)
show('cmd signed',frame(5,255,190,76,cl,152,key=key,link=1,ts=0x0000123456789A))
import hmac
print('derived', hmac.new(bytes([0xAB]*32), b'pheromesh mavlink signing key v1', hashlib.sha256).hexdigest())
