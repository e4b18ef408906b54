#!/usr/bin/env bash
# Creates DDS Security credentials for omnisweep (docs/security.md): a certificate authority, the
# domain governance document and one identity per name with its permissions document, the two
# documents signed by the CA (S/MIME, as the DDS Security builtin plugins read them).
#
#   make-credentials.sh DIR [NAME:ROLE ...]      default: server:server viewer:viewer status:status
#
# ROLE is what the identity may do on every topic prefix:
#   server   publish <prefix>/description, <prefix>/rgbd, <prefix>/status, the optional
#            <prefix>/confidence and the ROS 2 topics rt/* (omnisweep-server, omnisweep-play)
#   viewer   subscribe to all of them (omnisweep-view, omnisweep-subscribe, omnisweep-record, SDK
#            apps, ROS 2 nodes given this identity with SROS2)
#   status   subscribe to <prefix>/status only (monitoring)
# Each DIR/NAME/ is a folder to give --security: identity_ca.pem, cert.pem, key.pem (keep it
# private), permissions_ca.pem, governance.p7s, permissions.p7s. DIR/ca/ keeps the CA; an
# existing CA is reused, so identities can be added later. Governance: only authenticated
# participants join domains 0-232; discovery, liveliness and every omnisweep topic's data are
# encrypted (AES-GCM) and access-controlled.
set -euo pipefail
[[ $# -ge 1 ]] || { sed -n '2,17p' "$0" >&2; exit 2; }
dir=$1
shift
identities=("$@")
((${#identities[@]})) || identities=(server:server viewer:viewer status:status)
command -v openssl >/dev/null || { echo "make-credentials: needs openssl" >&2; exit 1; }
mkdir -p "$dir/ca"
ca=$dir/ca
days=3650

if [[ ! -f $ca/ca.pem ]]; then
  openssl ecparam -name prime256v1 -genkey -noout -out "$ca/ca.key" 2>/dev/null
  openssl req -x509 -new -key "$ca/ca.key" -sha256 -days "$days" \
    -subj "/O=omnisweep/CN=omnisweep CA" -out "$ca/ca.pem"
  chmod 600 "$ca/ca.key"
fi

topic_rule() {  # one topic expression of the governance document
  cat <<XML
        <topic_rule>
          <topic_expression>$1</topic_expression>
          <enable_discovery_protection>true</enable_discovery_protection>
          <enable_liveliness_protection>true</enable_liveliness_protection>
          <enable_read_access_control>true</enable_read_access_control>
          <enable_write_access_control>true</enable_write_access_control>
          <metadata_protection_kind>ENCRYPT</metadata_protection_kind>
          <data_protection_kind>ENCRYPT</data_protection_kind>
        </topic_rule>
XML
}

cat > "$ca/governance.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_governance.xsd">
  <domain_access_rules>
    <domain_rule>
      <domains><id_range><min>0</min><max>232</max></id_range></domains>
      <allow_unauthenticated_participants>false</allow_unauthenticated_participants>
      <enable_join_access_control>true</enable_join_access_control>
      <discovery_protection_kind>ENCRYPT</discovery_protection_kind>
      <liveliness_protection_kind>ENCRYPT</liveliness_protection_kind>
      <rtps_protection_kind>NONE</rtps_protection_kind>
      <topic_access_rules>
$(topic_rule "*/description")
$(topic_rule "*/rgbd")
$(topic_rule "*/status")
$(topic_rule "*/confidence")
$(topic_rule "rt/*")
      </topic_access_rules>
    </domain_rule>
  </domain_access_rules>
</dds>
XML
# -text: the builtin plugin reads the document as text/plain S/MIME (PLATFORM-NOTES.md).
openssl smime -sign -text -in "$ca/governance.xml" -out "$ca/governance.p7s" \
  -signer "$ca/ca.pem" -inkey "$ca/ca.key"

topics_xml() {  # <topics> for a space-separated list of expressions
  printf '          <topics>'
  local t
  local -a expressions
  read -r -a expressions <<< "$1"  # split on spaces, no glob expansion of the * patterns
  for t in "${expressions[@]}"; do printf '<topic>%s</topic>' "$t"; done
  printf '</topics>\n'
}

for entry in "${identities[@]}"; do
  name=${entry%%:*}
  role=${entry#*:}
  [[ $name =~ ^[A-Za-z0-9_-]+$ ]] || { echo "make-credentials: bad identity name '$name'" >&2; exit 2; }
  case $role in
    server) rules="          <publish>"$'\n'"$(topics_xml "*/description */rgbd */status */confidence rt/*")"$'\n'"          </publish>" ;;
    viewer) rules="          <subscribe>"$'\n'"$(topics_xml "*/description */rgbd */status */confidence rt/*")"$'\n'"          </subscribe>" ;;
    status) rules="          <subscribe>"$'\n'"$(topics_xml "*/status")"$'\n'"          </subscribe>" ;;
    *) echo "make-credentials: unknown role '$role' for $name (server, viewer or status)" >&2; exit 2 ;;
  esac
  out=$dir/$name
  mkdir -p "$out"
  openssl ecparam -name prime256v1 -genkey -noout -out "$out/key.pem" 2>/dev/null
  chmod 600 "$out/key.pem"
  openssl req -new -key "$out/key.pem" -subj "/O=omnisweep/CN=$name" -out "$out/cert.csr"
  openssl x509 -req -in "$out/cert.csr" -CA "$ca/ca.pem" -CAkey "$ca/ca.key" -CAcreateserial \
    -days "$days" -sha256 -out "$out/cert.pem" 2>/dev/null
  rm -f "$out/cert.csr"
  # The subject in RFC 2253 order, as the access-control plugin compares it.
  subject=$(openssl x509 -in "$out/cert.pem" -noout -subject -nameopt RFC2253 | sed 's/^subject=//')
  not_before=$(date -u +%Y-%m-%dT%H:%M:%S)
  not_after=$(date -u -d "+$days days" +%Y-%m-%dT%H:%M:%S)
  cat > "$out/permissions.xml" <<XML
<?xml version="1.0" encoding="UTF-8"?>
<dds xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance"
     xsi:noNamespaceSchemaLocation="http://www.omg.org/spec/DDS-SECURITY/20170901/omg_shared_ca_permissions.xsd">
  <permissions>
    <grant name="$name">
      <subject_name>$subject</subject_name>
      <validity><not_before>$not_before</not_before><not_after>$not_after</not_after></validity>
      <allow_rule>
        <domains><id_range><min>0</min><max>232</max></id_range></domains>
$rules
      </allow_rule>
      <default>DENY</default>
    </grant>
  </permissions>
</dds>
XML
  openssl smime -sign -text -in "$out/permissions.xml" -out "$out/permissions.p7s" \
    -signer "$ca/ca.pem" -inkey "$ca/ca.key"
  cp "$ca/ca.pem" "$out/identity_ca.pem"
  cp "$ca/ca.pem" "$out/permissions_ca.pem"
  cp "$ca/governance.p7s" "$out/governance.p7s"
  echo "make-credentials: $out ($role, subject $subject)"
done
