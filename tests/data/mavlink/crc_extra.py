# Prints, from the MAVLink project's message definitions, the wire field
# order and CRC_EXTRA of the messages common/mavlink speaks, to check
# messages.hpp against (run by hand; not part of the build):
#   python3 crc_extra.py DIR   (DIR holds minimal.xml, standard.xml, common.xml
#   of github.com/mavlink/mavlink message_definitions/v1.0)
import os, sys
import xml.etree.ElementTree as ET
d=sys.argv[1] if len(sys.argv)>1 else '.'
msgs={}
for f in ['minimal.xml','standard.xml','common.xml']:
    r=ET.parse(os.path.join(d,f)).getroot()
    for m in r.iter('message'):
        msgs[int(m.get('id'))]=m
sizes={'uint8_t':1,'int8_t':1,'char':1,'uint16_t':2,'int16_t':2,'uint32_t':4,'int32_t':4,'float':4,'uint64_t':8,'int64_t':8,'double':8}
from x25 import crc_acc, crcs
for mid in [0,1,33,30,74,246,253,76,77]:
    m=msgs[mid]
    fields=[];ext=False
    for c in m:
        if c.tag=='extensions': ext=True; continue
        if c.tag!='field': continue
        t=c.get('type'); arr=0
        if '[' in t: t,a=t.split('['); arr=int(a[:-1])
        base=t.replace('uint8_t_mavlink_version','uint8_t')
        fields.append((c.get('name'),base,arr,ext,t))
    core=[f for f in fields if not f[3]]
    core_sorted=sorted(core,key=lambda f:-sizes[f[1]])  # stable
    s=(m.get('name')+' ').encode()
    crc=crcs(s)
    for n,b,arr,e,t in core_sorted:
        crc=crcs((b+' ').encode(),crc); crc=crcs((n+' ').encode(),crc)
        if arr: crc=crc_acc(arr,crc)
    extra=(crc&0xff)^(crc>>8)
    off=0
    print(mid,m.get('name'),'crc_extra',extra)
    for n,b,arr,e,t in core_sorted+[f for f in fields if f[3]]:
        print('   @%d'%off,b,n,arr or '', 'EXT' if e else '')
        off+=sizes[b]*(arr or 1)
    print('   len',off)
