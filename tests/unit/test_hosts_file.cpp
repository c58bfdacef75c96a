// --hosts-file (launch/hosts_file.cpp, docs/deployment.md): the file's
// lines as the swarm's hosts in host-index order, what stands for --hosts,
// --dds-peers and --host-index, and every refusal naming the file and line.
// Name resolution and this host's addresses are a table here.
#include "launch/hosts_file.hpp"

#include <gtest/gtest.h>

#include <map>
#include <set>
#include <string>
#include <vector>

namespace pheromesh::cli {
namespace hosts_file_test {

// 10.0.0.x are addresses; the names below resolve as the table says; "bad!"
// is what the launcher's resolver refuses.
core::Result<std::vector<std::string>> resolve(const std::string& entry) {
  static const std::map<std::string, std::vector<std::string>> names{
      {"uav-host-1", {"10.0.0.2"}},
      {"gcs.lan", {"10.0.0.1"}},
      {"pods", {"10.1.0.5", "10.1.0.6"}},
      {"later", {}},
  };
  if (entry.rfind("10.", 0) == 0) return std::vector<std::string>{entry};
  const auto it = names.find(entry);
  if (it == names.end()) return std::vector<std::string>{};
  return it->second;
}

core::Result<HostsFile> parse(const std::string& text) { return parse_hosts_file(text, "hosts.txt", resolve); }

std::string error_of(const std::string& text) {
  const auto f = parse(text);
  EXPECT_FALSE(f.ok()) << text;
  return f.ok() ? std::string() : f.error().message;
}

TEST(HostsFile, LinesAreHostsInOrderAndCommentsAndBlankLinesAreSkipped) {
  const auto f = parse(
      "# the field swarm\n"
      "\n"
      "10.0.0.1   # ground station\n"
      "  uav-host-1\t\n"
      "#10.0.0.9\n"
      "10.0.0.3");  // no final newline
  ASSERT_TRUE(f.ok()) << f.error().message;
  ASSERT_EQ(f->hosts.size(), 3U);
  EXPECT_EQ(f->hosts[0].address, "10.0.0.1");
  EXPECT_EQ(f->hosts[0].line, 3U);
  EXPECT_EQ(f->hosts[1].name, "uav-host-1");
  EXPECT_EQ(f->hosts[1].address, "10.0.0.2");
  EXPECT_EQ(f->hosts[1].line, 4U);
  EXPECT_EQ(f->hosts[2].address, "10.0.0.3");
  EXPECT_EQ(f->hosts[2].line, 6U);
}

TEST(HostsFile, AFileWithoutAHostIsRefusedNamingIt) {
  for (const std::string text : {"", "\n\n", "# nothing yet\n   \n"}) {
    EXPECT_EQ(error_of(text), "hosts.txt: no host in it (one address or name per line, in host-index order)");
  }
}

TEST(HostsFile, AMalformedLineIsRefusedNamingFileLineAndWhy) {
  const struct {
    std::string text, says;
  } cases[] = {
      {"10.0.0.1\n10.0.0.2 10.0.0.3\n", "hosts.txt:2: '10.0.0.2 10.0.0.3': one host per line"},
      {"10.0.0.1,10.0.0.2\n", "hosts.txt:1: '10.0.0.1,10.0.0.2': one host per line, not a list"},
      {"\n10.0.0.1:7400\n", "hosts.txt:2: '10.0.0.1:7400': no port"},
      {"under_score\n", "hosts.txt:1: 'under_score': neither an IPv4 address nor a host name"},
      {"-lead\n", "hosts.txt:1: '-lead': neither an IPv4 address nor a host name"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_EQ(e.rfind(c.says, 0), 0U) << e;
  }
}

TEST(HostsFile, ANameThatDoesNotResolveOrResolvesToSeveralAddressesIsRefused) {
  EXPECT_EQ(error_of("10.0.0.1\nlater\n"), "hosts.txt:2: 'later': does not resolve");
  EXPECT_EQ(error_of("pods\n"),
            "hosts.txt:1: 'pods': resolves to 2 addresses (10.1.0.5, 10.1.0.6); each line names one host: write its "
            "address");
  // The resolver's own refusal, with the file and line put in front.
  const auto f =
      parse_hosts_file("10.0.0.1\nx\n", "h", [](const std::string& e) -> core::Result<std::vector<std::string>> {
        if (e == "x") return core::Error{"resolver says no"};
        return std::vector<std::string>{e};
      });
  ASSERT_FALSE(f.ok());
  EXPECT_EQ(f.error().message, "h:2: 'x': resolver says no");
}

TEST(HostsFile, AHostListedTwiceByAddressOrByNameIsRefused) {
  EXPECT_EQ(error_of("10.0.0.1\n10.0.0.2\n10.0.0.1\n"),
            "hosts.txt:3: '10.0.0.1' is 10.0.0.1, as line 1 ('10.0.0.1', host 0) is: every host once");
  EXPECT_EQ(error_of("10.0.0.2\n# the same one by its name\nuav-host-1\n"),
            "hosts.txt:3: 'uav-host-1' is 10.0.0.2, as line 1 ('10.0.0.2', host 0) is: every host once");
}

HostsFile three_hosts() { return parse("10.0.0.1\nuav-host-1\n10.0.0.3\n").value(); }

TEST(HostsFile, ItStandsForHostsAndDdsPeersAndTheGivenHostIndex) {
  HostsFlags flags;
  flags.host_index = 2;
  const auto c = choose_host(three_hosts(), flags, [](const std::string&) { return false; });
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->hosts, 3U);
  EXPECT_EQ(c->host_index, 2U);
  EXPECT_EQ(c->dds_peers, "10.0.0.1,10.0.0.2,10.0.0.3");
  flags.host_index = 3;
  const auto past = choose_host(three_hosts(), flags, [](const std::string&) { return true; });
  ASSERT_FALSE(past.ok());
  EXPECT_EQ(past.error().message, "--host-index 3 is not below the 3 hosts of --hosts-file hosts.txt");
}

TEST(HostsFile, WithoutHostIndexTheOneEntryThatIsThisHostIsTaken) {
  const std::set<std::string> mine{"127.0.0.1", "10.0.0.2"};
  const auto c = choose_host(three_hosts(), {}, [&](const std::string& a) { return mine.count(a) > 0; });
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c->host_index, 1U);

  const auto none = choose_host(three_hosts(), {}, [](const std::string&) { return false; });
  ASSERT_FALSE(none.ok());
  EXPECT_EQ(none.error().message,
            "--hosts-file hosts.txt: no entry is an address of this host; give --host-index, or list this host by an "
            "address one of its interfaces has");
  const auto several = choose_host(three_hosts(), {}, [](const std::string& a) { return a != "10.0.0.1"; });
  ASSERT_FALSE(several.ok());
  EXPECT_EQ(several.error().message,
            "--hosts-file hosts.txt: several entries are addresses of this host (host 1 (line 2, uav-host-1 = "
            "10.0.0.2), host 2 (line 3, 10.0.0.3)); give --host-index");
}

TEST(HostsFile, HostsOrDdsPeersGivenBesideItAreRefused) {
  const auto local = [](const std::string&) { return false; };
  HostsFlags hosts;
  hosts.hosts = 3;
  hosts.host_index = 0;
  const auto h = choose_host(three_hosts(), hosts, local);
  ASSERT_FALSE(h.ok());
  EXPECT_EQ(h.error().message, "--hosts-file hosts.txt gives --hosts (3 hosts): leave --hosts 3 out");
  HostsFlags peers;
  peers.host_index = 0;
  peers.dds_peers = "10.0.0.1,10.0.0.2,10.0.0.3";
  peers.dds_peers_from = "$PHEROMESH_DDS_PEERS";
  const auto p = choose_host(three_hosts(), peers, local);
  ASSERT_FALSE(p.ok());
  EXPECT_EQ(p.error().message,
            "--hosts-file hosts.txt gives --dds-peers (every host's address, in its order): leave "
            "$PHEROMESH_DDS_PEERS (10.0.0.1,10.0.0.2,10.0.0.3) out");
  // attach: the peers, or the same refusal.
  EXPECT_EQ(attach_peers(three_hosts(), {}).value(), "10.0.0.1,10.0.0.2,10.0.0.3");
  peers.dds_peers_from = "--dds-peers";
  EXPECT_FALSE(attach_peers(three_hosts(), peers).ok());
}

}  // namespace hosts_file_test
}  // namespace pheromesh::cli
